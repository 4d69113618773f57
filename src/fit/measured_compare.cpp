// Predicted against measured effective NDFs (include/microbrdf/measured_compare.hpp).
#include "microbrdf/measured_compare.hpp"

#include <cmath>

#include "microbrdf/error.hpp"
#include "microbrdf/ndf_convolve.hpp"

namespace microbrdf {
namespace {

// Convolution with a measured signature S (a small lobe about the pole): each predicted node's
// mass is moved along S's slope offsets, i.e. P * S on the disk in slope-offset approximation
// (the signatures are ~1 deg wide, where disk offsets and angles agree to < 1e-4 relative).
TabulatedNdf convolve_with_signature(const TabulatedNdf& p, const TabulatedNdf& s) {
  const TabulatedNdf sig = s.resampled(p.resolution());
  const std::size_t n = p.resolution();
  const long c = static_cast<long>(n / 2);
  std::vector<std::pair<long, long>> off;
  std::vector<double> w;
  double wsum = 0;
  for (std::size_t iy = 0; iy < n; ++iy)
    for (std::size_t ix = 0; ix < n; ++ix) {
      const double v = sig.at(ix, iy);
      if (v > 1e-6 * sig.at(std::size_t(c), std::size_t(c)) && std::isfinite(v)) {
        off.push_back({long(ix) - c, long(iy) - c});
        w.push_back(v);
        wsum += v;
      }
    }
  if (!(wsum > 0)) throw InputError("the instrument signature has no mass");
  TabulatedNdf out(n);
  for (std::size_t iy = 0; iy < n; ++iy)
    for (std::size_t ix = 0; ix < n; ++ix) {
      const double v = p.at(ix, iy);
      if (!(v > 0)) continue;
      for (std::size_t k = 0; k < off.size(); ++k) {
        const long x = long(ix) + off[k].first, y = long(iy) + off[k].second;
        if (x < 0 || y < 0 || x >= long(n) || y >= long(n)) continue;
        out.at(std::size_t(x), std::size_t(y)) += v * w[k] / wsum;
      }
    }
  out.clear_outside_disk();
  out.meta = p.meta;
  return out;
}

}  // namespace

TabulatedNdf instrument_view(const TabulatedNdf& predicted, std::size_t resolution, double fwhm,
                             const TabulatedNdf* instrument) {
  TabulatedNdf p = instrument ? convolve_with_signature(predicted, *instrument)
                              : convolve_angular_gaussian(predicted, fwhm);
  TabulatedNdf out(resolution);
  for (std::size_t iy = 0; iy < resolution; ++iy)
    for (std::size_t ix = 0; ix < resolution; ++ix)
      out.at(ix, iy) = p.eval_disk(out.node_x(ix), out.node_y(iy));
  out.meta = p.meta;
  return out;
}

NdfComparison compare_ndfs(const TabulatedNdf& measured, const TabulatedNdf& predicted, double fwhm,
                           const TabulatedNdf* instrument) {
  const std::size_t n = measured.resolution();
  const TabulatedNdf p = instrument_view(predicted, n, fwhm, instrument);
  NdfComparison r;
  double mp = 0, pp = 0, mm = 0, msum = 0, psum = 0;
  for (std::size_t iy = 0; iy < n; ++iy)
    for (std::size_t ix = 0; ix < n; ++ix) {
      const double x = measured.node_x(ix), y = measured.node_y(iy);
      const double m = measured.at(ix, iy);
      if (x * x + y * y >= 1 || !std::isfinite(m)) continue;
      const double v = p.at(ix, iy);
      mp += m * v;
      pp += v * v;
      mm += m * m;
      msum += std::max(m, 0.0);
      psum += std::max(v, 0.0);
      ++r.nodes;
    }
  if (r.nodes == 0 || !(mm > 0)) throw InputError("the measured table has no measured node");
  r.scale = pp > 0 ? mp / pp : 0;
  double e2 = 0, h2 = 0;
  for (std::size_t iy = 0; iy < n; ++iy)
    for (std::size_t ix = 0; ix < n; ++ix) {
      const double x = measured.node_x(ix), y = measured.node_y(iy);
      const double m = measured.at(ix, iy);
      if (x * x + y * y >= 1 || !std::isfinite(m)) continue;
      const double v = p.at(ix, iy);
      e2 += (m - r.scale * v) * (m - r.scale * v);
      if (msum > 0 && psum > 0) {
        const double d = std::sqrt(std::max(m, 0.0) / msum) - std::sqrt(std::max(v, 0.0) / psum);
        h2 += d * d;
      }
    }
  r.relative_l2 = std::sqrt(e2 / mm);
  r.hellinger = std::sqrt(0.5 * h2);
  FitOptions fo;
  fo.model = FitModel::Ggx;
  r.measured_fit = fit_ndf(measured, fo);
  r.predicted_fit = fit_ndf(p, fo);
  r.alpha_x_ratio = r.predicted_fit.params.alpha_x / r.measured_fit.params.alpha_x;
  r.alpha_y_ratio = r.predicted_fit.params.alpha_y / r.measured_fit.params.alpha_y;
  return r;
}

}  // namespace microbrdf
