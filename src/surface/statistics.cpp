#include "microbrdf/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/fft.hpp"

namespace microbrdf {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The linear autocorrelation sums of a scan's valid, mean-removed heights, sum_p h(p) h(p+l), and
// the number of valid pairs per lag, by zero-padded in-place FFTs (one buffer per quantity, no
// copies). When every sample is valid the pair count is (nx - |lx|)(ny - |ly|) in closed form and
// the mask is not transformed.
class LagSums {
 public:
  explicit LagSums(const Surface& s)
      : nx_(s.nx),
        ny_(s.ny),
        // Pad to >= 2n-1 so circular correlation equals linear correlation.
        px_(detail::fft_good_size(2 * s.nx - 1)),
        py_(detail::fft_good_size(2 * s.ny - 1)),
        stride_(2 * (px_ / 2 + 1)) {
    const double mean = s.valid_mean();
    const bool all_valid = s.valid_count() == s.size();
    hh_.assign(py_ * stride_, 0.0);
    if (!all_valid) vv_.assign(py_ * stride_, 0.0);
    for (std::size_t iy = 0; iy < s.ny; ++iy)
      for (std::size_t ix = 0; ix < s.nx; ++ix) {
        const std::size_t i = iy * s.nx + ix;
        if (!s.valid[i]) continue;
        hh_[iy * stride_ + ix] = s.z[i] - mean;
        if (!all_valid) vv_[iy * stride_ + ix] = 1.0;
      }
    detail::autocorrelation_sums_inplace(px_, py_, hh_);
    if (!all_valid) detail::autocorrelation_sums_inplace(px_, py_, vv_);
  }

  // sum h h / pairs at lag (lx, ly), NaN where fewer than min_overlap pairs; |l| < n.
  double mean_product(long lx, long ly, std::size_t min_overlap) const {
    const std::size_t row =
        static_cast<std::size_t>((ly + static_cast<long>(py_)) % static_cast<long>(py_));
    const std::size_t col =
        static_cast<std::size_t>((lx + static_cast<long>(px_)) % static_cast<long>(px_));
    const double pairs = vv_.empty()
                             ? static_cast<double>((nx_ - static_cast<std::size_t>(std::labs(lx))) *
                                                   (ny_ - static_cast<std::size_t>(std::labs(ly))))
                             : vv_[row * stride_ + col];
    return pairs >= static_cast<double>(min_overlap) - 0.5 ? hh_[row * stride_ + col] / pairs
                                                           : kNaN;
  }

 private:
  std::size_t nx_, ny_, px_, py_, stride_;
  std::vector<double> hh_, vv_;
};

// Mean of value(lx, ly) (NaN skipped) in annuli of width dr = min(dx, dy) about the origin, over
// the lags |lx| <= bx, |ly| <= by in row order; only annuli b with (b + 1/2) dr <= whole are
// kept (every lag they hold lies in the box).
template <class Value>
RadialProfile annulus_means(long bx, long by, double dx, double dy, std::size_t nbins, double whole,
                            Value&& value) {
  const double dr = std::min(dx, dy);
  std::vector<double> sum(nbins, 0.0), cnt(nbins, 0.0);
  for (long ly = -by; ly <= by; ++ly)
    for (long lx = -bx; lx <= bx; ++lx) {
      const double v = value(lx, ly);
      if (!std::isfinite(v)) continue;
      const double r = std::hypot(static_cast<double>(lx) * dx, static_cast<double>(ly) * dy);
      const auto b = static_cast<std::size_t>(std::lround(r / dr));
      if (b >= nbins) continue;
      sum[b] += v;
      cnt[b] += 1;
    }
  RadialProfile p;
  for (std::size_t b = 0; b < nbins && (static_cast<double>(b) + 0.5) * dr <= whole; ++b) {
    if (cnt[b] == 0) continue;
    p.r.push_back(static_cast<double>(b) * dr);
    p.value.push_back(sum[b] / cnt[b]);
  }
  return p;
}

// Annuli of a lag grid: width min(dx, dy), out to the shorter side of the scan.
std::size_t annulus_count(std::size_t nx, std::size_t ny, double dx, double dy) {
  const double rmax = std::min(static_cast<double>(nx - 1) * dx, static_cast<double>(ny - 1) * dy);
  return static_cast<std::size_t>(rmax / std::min(dx, dy)) + 1;
}

// Radial average of the normalised ACF (as radial_average) and its 1/e crossing, over a box of
// lags that doubles until the crossing lies in annuli the box holds whole: correlation lengths
// are usually far shorter than the scan, and the annuli's sums are the same, term for term and
// in the same order, as over the whole lag grid.
double radial_correlation_length(const LagSums& sums, double c0, const Surface& s,
                                 std::size_t min_overlap) {
  const double dr = std::min(s.dx, s.dy);
  const std::size_t nbins = annulus_count(s.nx, s.ny, s.dx, s.dy);
  const long last_x = static_cast<long>(s.nx) - 1, last_y = static_cast<long>(s.ny) - 1;
  for (double reach = 64 * dr;; reach *= 2) {
    const long bx = std::min(last_x, static_cast<long>(std::ceil(reach / s.dx)));
    const long by = std::min(last_y, static_cast<long>(std::ceil(reach / s.dy)));
    // Lags outside the box lie farther than `whole`: annuli below it are complete.
    const double whole = std::min(bx == last_x ? HUGE_VAL : static_cast<double>(bx) * s.dx,
                                  by == last_y ? HUGE_VAL : static_cast<double>(by) * s.dy);
    const RadialProfile p = annulus_means(bx, by, s.dx, s.dy, nbins, whole, [&](long lx, long ly) {
      return sums.mean_product(lx, ly, min_overlap) / c0;
    });
    const double tau = correlation_length(p.r, p.value);
    if (std::isfinite(tau) || (bx == last_x && by == last_y)) return tau;
  }
}

constexpr std::size_t kMinOverlap = 64;  // as autocorrelation()'s default

}  // namespace

Autocorrelation autocorrelation(const Surface& s, std::size_t min_overlap) {
  Autocorrelation acf;
  acf.nx = s.nx;
  acf.ny = s.ny;
  acf.dx = s.dx;
  acf.dy = s.dy;
  const LagSums sums(s);
  const std::size_t lx_n = 2 * s.nx - 1, ly_n = 2 * s.ny - 1;
  acf.value.assign(lx_n * ly_n, kNaN);
  const double c0 = sums.mean_product(0, 0, min_overlap);
  for (long ly = -static_cast<long>(s.ny) + 1; ly < static_cast<long>(s.ny); ++ly)
    for (long lx = -static_cast<long>(s.nx) + 1; lx < static_cast<long>(s.nx); ++lx)
      acf.value[static_cast<std::size_t>(ly + static_cast<long>(s.ny) - 1) * lx_n +
                static_cast<std::size_t>(lx + static_cast<long>(s.nx) - 1)] =
          c0 > 0 ? sums.mean_product(lx, ly, min_overlap) / c0 : kNaN;
  return acf;
}

double autocorrelation_direct(const Surface& s, long lx, long ly) {
  const double mean = s.valid_mean();
  auto sums = [&](long ax, long ay) {
    double sum = 0;
    std::size_t n = 0;
    for (long iy = 0; iy < static_cast<long>(s.ny); ++iy) {
      long jy = iy + ay;
      if (jy < 0 || jy >= static_cast<long>(s.ny)) continue;
      for (long ix = 0; ix < static_cast<long>(s.nx); ++ix) {
        long jx = ix + ax;
        if (jx < 0 || jx >= static_cast<long>(s.nx)) continue;
        std::size_t a = static_cast<std::size_t>(iy) * s.nx + static_cast<std::size_t>(ix);
        std::size_t b = static_cast<std::size_t>(jy) * s.nx + static_cast<std::size_t>(jx);
        if (!s.valid[a] || !s.valid[b]) continue;
        sum += (s.z[a] - mean) * (s.z[b] - mean);
        ++n;
      }
    }
    return n ? sum / static_cast<double>(n) : kNaN;
  };
  return sums(lx, ly) / sums(0, 0);
}

RadialProfile radial_average(const Autocorrelation& acf) {
  return annulus_means(static_cast<long>(acf.nx) - 1, static_cast<long>(acf.ny) - 1, acf.dx, acf.dy,
                       annulus_count(acf.nx, acf.ny, acf.dx, acf.dy), HUGE_VAL,
                       [&](long lx, long ly) { return acf.at(lx, ly); });
}

double correlation_length(const std::vector<double>& r, const std::vector<double>& acf) {
  const double target = std::exp(-1.0);
  for (std::size_t i = 1; i < r.size() && i < acf.size(); ++i) {
    if (!std::isfinite(acf[i]) || !std::isfinite(acf[i - 1])) return kNaN;
    if (acf[i] <= target) {
      double t = (acf[i - 1] - target) / (acf[i - 1] - acf[i]);
      return r[i - 1] + t * (r[i] - r[i - 1]);
    }
  }
  return kNaN;
}

Psd power_spectrum(const Surface& s) {
  const double mean = s.valid_mean();
  std::vector<double> h(s.size(), 0.0);
  std::size_t nvalid = 0;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (s.valid[i]) {
      h[i] = s.z[i] - mean;
      ++nvalid;
    }
  auto spec = detail::fft2_r2c(s.nx, s.ny, h);
  const std::size_t hx = s.nx / 2 + 1;
  const double dk =
      2 * M_PI / std::max(static_cast<double>(s.nx) * s.dx, static_cast<double>(s.ny) * s.dy);
  const std::size_t nbins = std::min(s.nx, s.ny) / 2 + 1;
  std::vector<double> sum(nbins, 0.0), cnt(nbins, 0.0);
  const double norm = s.dx * s.dy / static_cast<double>(nvalid);
  for (std::size_t iy = 0; iy < s.ny; ++iy) {
    double ky = detail::fft_freq(iy, s.ny) / s.dy;
    for (std::size_t ix = 0; ix < hx; ++ix) {
      double kx = detail::fft_freq(ix, s.nx) / s.dx;
      auto b = static_cast<std::size_t>(std::lround(std::hypot(kx, ky) / dk));
      if (b >= nbins) continue;
      // The half spectrum stands for its mirror image too (except the self-conjugate columns).
      double w = (ix == 0 || (s.nx % 2 == 0 && ix == s.nx / 2)) ? 1.0 : 2.0;
      sum[b] += w * std::norm(spec[iy * hx + ix]) * norm;
      cnt[b] += w;
    }
  }
  Psd p;
  for (std::size_t b = 1; b < nbins; ++b) {
    if (cnt[b] == 0) continue;
    p.k.push_back(static_cast<double>(b) * dk);
    p.s.push_back(sum[b] / cnt[b]);
  }
  return p;
}

SurfaceStats compute_stats(const Surface& s) {
  SurfaceStats st;
  st.nx = s.nx;
  st.ny = s.ny;
  st.dx = s.dx;
  st.dy = s.dy;
  st.valid_count = s.valid_count();
  st.valid_fraction = s.valid_fraction();
  st.mean = s.valid_mean();
  st.min = std::numeric_limits<double>::infinity();
  st.max = -st.min;
  double m2 = 0, m3 = 0, m4 = 0, ma = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (!s.valid[i]) continue;
    double d = s.z[i] - st.mean;
    st.min = std::min(st.min, s.z[i]);
    st.max = std::max(st.max, s.z[i]);
    m2 += d * d;
    m3 += d * d * d;
    m4 += d * d * d * d;
    ma += std::fabs(d);
  }
  const double n = static_cast<double>(st.valid_count);
  st.sq = std::sqrt(m2 / n);
  st.sa = ma / n;
  st.skewness = st.sq > 0 ? (m3 / n) / (st.sq * st.sq * st.sq) : 0;
  st.kurtosis = st.sq > 0 ? (m4 / n) / (st.sq * st.sq * st.sq * st.sq) : 0;

  // Central-difference slopes where both neighbours are valid.
  double sx = 0, sy = 0;
  std::size_t nxs = 0, nys = 0;
  for (std::size_t iy = 0; iy < s.ny; ++iy)
    for (std::size_t ix = 0; ix < s.nx; ++ix) {
      if (ix >= 1 && ix + 1 < s.nx && s.valid[iy * s.nx + ix - 1] && s.valid[iy * s.nx + ix + 1]) {
        double g = (s.z[iy * s.nx + ix + 1] - s.z[iy * s.nx + ix - 1]) / (2 * s.dx);
        sx += g * g;
        ++nxs;
      }
      if (iy >= 1 && iy + 1 < s.ny && s.valid[(iy - 1) * s.nx + ix] &&
          s.valid[(iy + 1) * s.nx + ix]) {
        double g = (s.z[(iy + 1) * s.nx + ix] - s.z[(iy - 1) * s.nx + ix]) / (2 * s.dy);
        sy += g * g;
        ++nys;
      }
    }
  st.slope_rms_x = nxs ? std::sqrt(sx / static_cast<double>(nxs)) : kNaN;
  st.slope_rms_y = nys ? std::sqrt(sy / static_cast<double>(nys)) : kNaN;
  st.slope_samples_x = nxs;
  st.slope_samples_y = nys;

  // Correlation lengths from one set of lag sums: the axis cuts and the radial average, without
  // forming the whole normalised lag grid.
  if (st.sq > 0 && s.nx > 1) {
    const LagSums sums(s);
    const double c0 = sums.mean_product(0, 0, kMinOverlap);
    auto cut = [&](std::size_t n, double d, bool along_x) {
      std::vector<double> r, a;
      for (long l = 0; l < static_cast<long>(n); ++l) {
        r.push_back(static_cast<double>(l) * d);
        a.push_back(c0 > 0 ? sums.mean_product(along_x ? l : 0, along_x ? 0 : l, kMinOverlap) / c0
                           : kNaN);
      }
      return correlation_length(r, a);
    };
    st.corr_length_x = cut(s.nx, s.dx, true);
    if (s.ny > 1) {
      st.corr_length_y = cut(s.ny, s.dy, false);
      st.corr_length = c0 > 0 ? radial_correlation_length(sums, c0, s, kMinOverlap) : kNaN;
    } else {  // a single profile: only the x lag exists
      st.corr_length_y = kNaN;
      st.corr_length = st.corr_length_x;
    }
  } else {
    st.corr_length_x = st.corr_length_y = st.corr_length = kNaN;
  }
  return st;
}

}  // namespace microbrdf
