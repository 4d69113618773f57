// A tabulated NDF as a microfacet distribution (include/microbrdf/tabulated_distribution.hpp).
#include "microbrdf/tabulated_distribution.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include "core/fast_atan2.hpp"
#include "microbrdf/error.hpp"
#include "tabulated_distribution_vn.hpp"

namespace microbrdf {
namespace {
constexpr double kPi = 3.14159265358979323846;
}

TabulatedSampling parse_tabulated_sampling(const std::string& name) {
  if (name == "visible") return TabulatedSampling::Visible;
  if (name == "ndf") return TabulatedSampling::Ndf;
  throw InputError("unknown tabulated sampling '" + name + "' (visible | ndf)");
}

std::string to_string(TabulatedSampling s) {
  return s == TabulatedSampling::Visible ? "visible" : "ndf";
}

TabulatedDistribution::~TabulatedDistribution() = default;

std::size_t TabulatedDistribution::sampling_memory_bytes() const {
  return vn_ ? vn_->memory_bytes() : 0;
}

TabulatedDistribution::TabulatedDistribution(TabulatedNdf ndf,
                                             const TabulatedDistributionOptions& opt)
    : ndf_(std::make_unique<TabulatedNdf>(std::move(ndf))), opt_(opt) {
  if (opt_.theta_steps < 2 || opt_.phi_steps < 4 || opt_.sigma_bins < 2)
    throw InputError("tabulated distribution: sigma+ grid too small");
  const std::size_t n = ndf_->resolution();
  for (double v : ndf_->values())
    if (!std::isfinite(v)) throw InputError("tabulated NDF: non-finite value in the table");
  try {
    sampler_ = std::make_unique<NdfSampler>(*ndf_);
  } catch (const std::invalid_argument&) {
    throw InputError("tabulated NDF: no positive mass inside the unit disk");
  }
  z_ = sampler_->normalisation();
  if (!(z_ > 0) || !std::isfinite(z_))
    throw InputError("tabulated NDF: no positive mass inside the unit disk");
  inv_z_ = 1 / z_;

  // Slope bins: cell (cx, cy) of the node grid -> bin (cx * b / (n - 1), cy * b / (n - 1)).
  // Per bin: the moments of the interpolant  integral D {1, m_x/m_z, m_y/m_z} dm_x dm_y  over its
  // cells (inside the disk). Cells well inside the disk (all corners at r <= 0.98): 3 x 3
  // Gauss-Legendre (the integrands are smooth there). Cells reaching r > 0.98: 32 midpoint
  // sub-rows in y, each integrated exactly in x (D is linear in x along a row, and the
  // antiderivatives of x/sqrt(c^2 - x^2), x^2/sqrt(c^2 - x^2) and 1/sqrt(c^2 - x^2) are
  // elementary), which handles the 1/m_z singularity at the rim.
  const std::size_t cells = n - 1;
  bins_ = std::min(opt_.sigma_bins, cells);
  std::vector<double> m0(bins_ * bins_, 0), mx(m0.size(), 0), my(m0.size(), 0);
  const double h = ndf_->spacing();
  const double gx[3] = {0.5 - std::sqrt(0.15), 0.5, 0.5 + std::sqrt(0.15)};
  const double gw[3] = {5.0 / 18, 8.0 / 18, 5.0 / 18};
  constexpr int kRows = 32;
  for (std::size_t cy = 0; cy < cells; ++cy) {
    const double y0 = ndf_->node_y(cy), y1 = y0 + h;
    const double ynear = y0 > 0 ? y0 : (y1 < 0 ? y1 : 0.0), yfar = std::max(-y0, y1);
    const std::size_t by = cy * bins_ / cells;
    for (std::size_t cx = 0; cx < cells; ++cx) {
      const double a = ndf_->at(cx, cy), b = ndf_->at(cx + 1, cy), c = ndf_->at(cx, cy + 1),
                   d = ndf_->at(cx + 1, cy + 1);
      if (a == 0 && b == 0 && c == 0 && d == 0) continue;
      const double x0 = ndf_->node_x(cx), x1 = x0 + h;
      const double xnear = x0 > 0 ? x0 : (x1 < 0 ? x1 : 0.0), xfar = std::max(-x0, x1);
      if (xnear * xnear + ynear * ynear >= 1) continue;  // outside the disk
      double s0 = 0, sx = 0, sy = 0;
      if (xfar * xfar + yfar * yfar <= 0.98 * 0.98) {
        for (int j = 0; j < 3; ++j)
          for (int i = 0; i < 3; ++i) {
            const double tx = gx[i], ty = gx[j], x = x0 + h * tx, y = y0 + h * ty;
            const double v =
                ((1 - ty) * ((1 - tx) * a + tx * b) + ty * ((1 - tx) * c + tx * d)) * gw[i] * gw[j];
            const double inv_mz = 1 / std::sqrt(1 - x * x - y * y);
            s0 += v;
            sx += v * x * inv_mz;
            sy += v * y * inv_mz;
          }
        s0 *= h * h;
        sx *= h * h;
        sy *= h * h;
      } else {
        const double dy = h / kRows;
        for (int k = 0; k < kRows; ++k) {
          const double ty = (k + 0.5) / kRows, y = y0 + h * ty, c2 = 1 - y * y;
          if (c2 <= 0) continue;
          const double cc = std::sqrt(c2);
          const double xa = std::max(x0, -cc), xb = std::min(x1, cc);
          if (xb <= xa) continue;
          const double left = (1 - ty) * a + ty * c, right = (1 - ty) * b + ty * d;
          const double B = (right - left) / h, A = left - B * x0;
          auto sq = [&](double x) { return std::sqrt(std::max(0.0, c2 - x * x)); };
          auto as = [&](double x) { return std::asin(std::clamp(x / cc, -1.0, 1.0)); };
          const double sa = sq(xa), sb = sq(xb), da = as(xb) - as(xa);
          s0 += dy * (A * (xb - xa) + 0.5 * B * (xb * xb - xa * xa));
          sx += dy * (A * (sa - sb) + B * (0.5 * c2 * da - 0.5 * (xb * sb - xa * sa)));
          sy += dy * y * (A * da + B * (sa - sb));
        }
      }
      const std::size_t bin = by * bins_ + cx * bins_ / cells;
      m0[bin] += s0;
      mx[bin] += sx;
      my[bin] += sy;
    }
  }
  double total = 0;
  for (double v : m0)
    if (v > 0) total += v;
  if (!(total > 0)) throw InputError("tabulated NDF: no positive mass inside the unit disk");
  for (std::size_t b = 0; b < m0.size(); ++b) {
    if (!(m0[b] > 0)) continue;  // (negative table values: such bins are left out)
    bm_.push_back(m0[b] / total);
    bp_.push_back(mx[b] / m0[b]);
    bq_.push_back(my[b] / m0[b]);
  }

  // sigma+ on the (theta, phi) grid.
  const std::size_t nt = opt_.theta_steps + 1, np = opt_.phi_steps;
  sigma_.assign(nt * np, 0);
  const double dt = 0.5 * kPi / static_cast<double>(opt_.theta_steps),
               dp = 2 * kPi / static_cast<double>(np);
  const auto nodes = static_cast<long>(nt * np);
#pragma omp parallel for schedule(dynamic, 16)
  for (long c = 0; c < nodes; ++c) {
    const auto it = static_cast<std::size_t>(c) / np, ip = static_cast<std::size_t>(c) % np;
    const double t = dt * static_cast<double>(it), p = dp * static_cast<double>(ip);
    sigma_[static_cast<std::size_t>(c)] =
        sigma_plus_direct(Vec3(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)));
  }
  // sigma+(n) = 1 up to rounding; make it exact so that G1(n) = 1 exactly.
  const double s_n = sigma_[0];
  for (double& v : sigma_) v /= s_n;
  for (double& v : bm_) v /= s_n;

  if (opt_.sampling == TabulatedSampling::Visible)
    vn_ = std::make_unique<detail::VisibleNormalTables>(*ndf_, opt_.vn_coarse, opt_.vn_theta_steps,
                                                        opt_.vn_phi_steps, opt_.vn_defensive);

  // lookup(): TabulatedNdf::eval_disk's constants, and the cells whose corners are all +0.
  d_ = ndf_->values().data();
  n_ = n;
  inv_h_ = 1.0 / ndf_->spacing();
  x0_ = ndf_->window().x0();
  y0_ = ndf_->window().y0();
  last_ = static_cast<double>(n - 1);
  top_ = static_cast<double>(n - 2);
  full_ = ndf_->window().full();
  words_ = (cells + 63) / 64;
  live_.assign(cells * words_, 0);
  auto nonzero = [](double v) { return std::bit_cast<std::uint64_t>(v) != 0; };
  for (std::size_t cy = 0; cy < cells; ++cy)
    for (std::size_t cx = 0; cx < cells; ++cx)
      if (nonzero(ndf_->at(cx, cy)) || nonzero(ndf_->at(cx + 1, cy)) ||
          nonzero(ndf_->at(cx, cy + 1)) || nonzero(ndf_->at(cx + 1, cy + 1)))
        live_[cy * words_ + cx / 64] |= std::uint64_t{1} << (cx % 64);
}

double TabulatedDistribution::lookup(const Vec3& m, TabulatedLookup& q) const {
  // TabulatedNdf::eval(m) * inv_z_ written out (the same operations in the same order), keeping
  // the cell for sampling_pdf; a cell of +0 corners gives +0 from its bit alone.
  q.e = 0;
  const double len = m.norm();
  q.mz = 0;
  if (!(len > 0) || m.z() <= 0) return 0.0;
  const double mx = m.x() / len, my = m.y() / len;
  if (!(mx * mx + my * my <= 1.0)) return 0.0;  // also rejects NaN
  const double fx = (mx - x0_) * inv_h_, fy = (my - y0_) * inv_h_;
  if (!full_ && !(fx >= 0 && fx <= last_ && fy >= 0 && fy <= last_)) return 0.0;
  const auto ix = static_cast<std::size_t>(std::clamp(std::floor(fx), 0.0, top_));
  const auto iy = static_cast<std::size_t>(std::clamp(std::floor(fy), 0.0, top_));
  if (!((live_[iy * words_ + ix / 64] >> (ix % 64)) & 1)) return 0.0;
  const double tx = fx - static_cast<double>(ix), ty = fy - static_cast<double>(iy);
  const double* r0 = d_ + iy * n_ + ix;
  const double* r1 = r0 + n_;
  const double e =
      (1 - ty) * ((1 - tx) * r0[0] + tx * r0[1]) + ty * ((1 - tx) * r1[0] + tx * r1[1]);
  q.e = e;
  q.mz = m.z() / len;
  q.cx = ix;
  q.cy = iy;
  return e * inv_z_;
}

TabulatedViewMix TabulatedDistribution::view_mix(const Vec3& v) const {
  return vn_ ? vn_->view_mix(v) : TabulatedViewMix{};
}

Vec3 TabulatedDistribution::sample_visible(const TabulatedViewMix& x, const Vec3& /*v*/, double u1,
                                           double u2) const {
  return vn_ ? vn_->sample(x, u1, u2) : sampler_->sample(u1, u2);
}

void TabulatedDistribution::prefetch_pdf(const TabulatedViewMix& x,
                                         const TabulatedLookup& q) const {
  if (vn_ && q.e > 0) vn_->prefetch(x, q.cx, q.cy);
}

double TabulatedDistribution::sampling_pdf(const TabulatedViewMix& x, const Vec3& m,
                                           const TabulatedLookup& q) const {
  // (VisibleNormalTables::pdf returns 0 wherever lookup left e at 0 or below)
  if (vn_) return q.e > 0 ? vn_->pdf_at(x, q.cx, q.cy, q.e, q.mz) : 0.0;
  return m.z() > 0 ? q.e * inv_z_ * m.z() : 0.0;
}

double TabulatedDistribution::sigma_plus_direct(const Vec3& k) const {
  const double kx = k.x(), ky = k.y(), kz = k.z();
  // Four running sums (a fixed order, whatever the thread count): one sum would wait for the
  // previous addition at every bin; this is the bulk of the constructor's time.
  double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
  const std::size_t nb = bm_.size(), n4 = nb - nb % 4;
  const double *m = bm_.data(), *p = bp_.data(), *q = bq_.data();
#ifdef __SSE2__
  // The same operations in the same order, two bins per instruction (s0 s1 | s2 s3).
  const __m128d vx = _mm_set1_pd(kx), vy = _mm_set1_pd(ky), vz = _mm_set1_pd(kz),
                zero = _mm_setzero_pd();
  __m128d a01 = zero, a23 = zero;
  for (std::size_t b = 0; b < n4; b += 4) {
    const __m128d t01 = _mm_add_pd(_mm_add_pd(vz, _mm_mul_pd(vx, _mm_loadu_pd(p + b))),
                                   _mm_mul_pd(vy, _mm_loadu_pd(q + b)));
    const __m128d t23 = _mm_add_pd(_mm_add_pd(vz, _mm_mul_pd(vx, _mm_loadu_pd(p + b + 2))),
                                   _mm_mul_pd(vy, _mm_loadu_pd(q + b + 2)));
    a01 = _mm_add_pd(a01, _mm_mul_pd(_mm_loadu_pd(m + b), _mm_max_pd(t01, zero)));
    a23 = _mm_add_pd(a23, _mm_mul_pd(_mm_loadu_pd(m + b + 2), _mm_max_pd(t23, zero)));
  }
  double lanes[4];
  _mm_storeu_pd(lanes, a01);
  _mm_storeu_pd(lanes + 2, a23);
  s0 = lanes[0];
  s1 = lanes[1];
  s2 = lanes[2];
  s3 = lanes[3];
#else
  for (std::size_t b = 0; b < n4; b += 4) {
    s0 += m[b] * std::max(0.0, kz + kx * p[b] + ky * q[b]);
    s1 += m[b + 1] * std::max(0.0, kz + kx * p[b + 1] + ky * q[b + 1]);
    s2 += m[b + 2] * std::max(0.0, kz + kx * p[b + 2] + ky * q[b + 2]);
    s3 += m[b + 3] * std::max(0.0, kz + kx * p[b + 3] + ky * q[b + 3]);
  }
#endif
  for (std::size_t b = n4; b < nb; ++b) s0 += m[b] * std::max(0.0, kz + kx * p[b] + ky * q[b]);
  return (s0 + s1) + (s2 + s3);
}

double TabulatedDistribution::sigma_plus(const Vec3& k) const {
  const std::size_t np = opt_.phi_steps;
  // The grid's angles of k (fast_atan2: within 3e-13 rad, far below the grid's spacing; this
  // look-up runs for every light direction of a render, where the C library's atan2 led the
  // profile). k is a direction, so x^2 + y^2 cannot overflow.
  const double st = std::sqrt(k.x() * k.x() + k.y() * k.y());
  double t = detail::fast_atan2(st, k.z()) * (static_cast<double>(opt_.theta_steps) / (0.5 * kPi));
  double p = detail::fast_atan2(k.y(), k.x());
  if (p < 0) p += 2 * kPi;
  p *= static_cast<double>(np) / (2 * kPi);
  t = std::clamp(t, 0.0, static_cast<double>(opt_.theta_steps));
  const auto it = std::min(static_cast<std::size_t>(t), opt_.theta_steps - 1);
  const auto ip = std::min(static_cast<std::size_t>(p), np - 1);
  const std::size_t ip1 = ip + 1 == np ? 0 : ip + 1;
  const double ft = t - static_cast<double>(it), fp = p - static_cast<double>(ip);
  const double* r0 = &sigma_[it * np];
  const double* r1 = r0 + np;
  return (1 - ft) * ((1 - fp) * r0[ip] + fp * r0[ip1]) + ft * ((1 - fp) * r1[ip] + fp * r1[ip1]);
}

double TabulatedDistribution::D(const Vec3& m) const {
  TabulatedLookup q;
  return lookup(m, q);  // = ndf_->eval(m) * inv_z_
}

double TabulatedDistribution::lambda(const Vec3& v) const {
  if (!(v.z() > 0)) return std::numeric_limits<double>::infinity();
  return sigma_plus(v) / v.z() - 1.0;
}

Vec3 TabulatedDistribution::sample_visible(const Vec3& v, double u1, double u2) const {
  return vn_ ? vn_->sample(v, u1, u2) : sampler_->sample(u1, u2);
}

double TabulatedDistribution::sampling_pdf(const Vec3& v, const Vec3& m) const {
  if (vn_) return vn_->pdf(v, m);
  return m.z() > 0 ? D(m) * m.z() : 0.0;
}

std::string TabulatedDistribution::describe() const {
  char b[256];
  std::snprintf(b, sizeof b,
                "tabulated NDF %zux%zu%s%s (sigma+ on %zux%zu theta,phi nodes from %zu^2 slope "
                "bins; samples %s)",
                ndf_->resolution(), ndf_->resolution(), ndf_->meta.method.empty() ? "" : " ",
                ndf_->meta.method.c_str(), opt_.theta_steps + 1, opt_.phi_steps, bins_,
                vn_ ? "approximate visible normals, exact pdf" : "D(m)(m.n)");
  return b;
}

}  // namespace microbrdf
