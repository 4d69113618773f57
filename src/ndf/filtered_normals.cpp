// Gaussian-weighted local plane fits at every sample (Dong 2015 section 5.1), computed with
// separable correlations of masked moment images (docs/theory.md §3.3: first-order normalized
// convolution). Coordinates inside are in units of the filter sigma for conditioning.
#include <cmath>
#include <vector>

#include "microbrdf/error.hpp"
#include "microbrdf/ndf_estimate.hpp"

namespace microbrdf {
namespace {

struct Kernel {
  long half = 0;                 // taps k in [-half, half]
  std::vector<double> g, u, u2;  // g(k), g(k) u_k, g(k) u_k^2 with u_k = k d / sigma
  double sum = 0;                // sum of g
};

Kernel make_kernel(double spacing, double sigma, double truncate) {
  Kernel k;
  k.half = static_cast<long>(std::floor(truncate * sigma / spacing));
  for (long i = -k.half; i <= k.half; ++i) {
    double u = static_cast<double>(i) * spacing / sigma;
    double g = std::exp(-0.5 * u * u);
    k.g.push_back(g);
    k.u.push_back(g * u);
    k.u2.push_back(g * u * u);
    k.sum += g;
  }
  return k;
}

// out[x] = sum_k in[x + k] * w[k + half] along rows (dir 0) or columns (dir 1); zero outside.
void correlate(const std::vector<double>& in, std::vector<double>& out, std::size_t nx,
               std::size_t ny, const std::vector<double>& w, long half, int dir) {
  out.assign(nx * ny, 0.0);
  const long n_along = static_cast<long>(dir == 0 ? nx : ny);
  const long lines = static_cast<long>(dir == 0 ? ny : nx);
  const std::size_t stride = dir == 0 ? 1 : nx;
#pragma omp parallel for schedule(static)
  for (long line = 0; line < lines; ++line) {
    const std::size_t base =
        dir == 0 ? static_cast<std::size_t>(line) * nx : static_cast<std::size_t>(line);
    for (long x = 0; x < n_along; ++x) {
      long k0 = std::max(-half, -x), k1 = std::min(half, n_along - 1 - x);
      double acc = 0;
      for (long k = k0; k <= k1; ++k)
        acc += in[base + static_cast<std::size_t>(x + k) * stride] *
               w[static_cast<std::size_t>(k + half)];
      out[base + static_cast<std::size_t>(x) * stride] = acc;
    }
  }
}

// Solves the 3x3 normal equations of the plane fit (moments in sigma units); returns false if
// the support is too thin or the system is ill-conditioned.
bool solve_plane(double m00, double m10, double m01, double m20, double m11, double m02, double b00,
                 double b10, double b01, double min_mass, double& bx, double& by) {
  if (!(m00 >= min_mass)) return false;
  // Reduce to the 2x2 system for the slopes: covariance of (u, v) and of (u, v) with h.
  const double cu = m10 / m00, cv = m01 / m00;
  const double suu = m20 - m10 * cu, svv = m02 - m01 * cv, suv = m11 - m10 * cv;
  const double shu = b10 - b00 * cu, shv = b01 - b00 * cv;
  const double det = suu * svv - suv * suv;
  if (!(det > 1e-10 * m00 * m00)) return false;
  bx = (shu * svv - shv * suv) / det;
  by = (shv * suu - shu * suv) / det;
  return true;
}

void set_normal(double bx_phys, double by_phys, double* m) {
  const double inv = 1.0 / std::sqrt(1.0 + bx_phys * bx_phys + by_phys * by_phys);
  m[0] = -bx_phys * inv;
  m[1] = -by_phys * inv;
  m[2] = inv;
}

void check_args(const Surface& s, double sigma, double truncate) {
  if (!(sigma > 0)) throw InputError("filter sigma must be positive");
  if (!(truncate >= 1)) throw InputError("kernel truncation must be >= 1 sigma");
  if (s.size() == 0) throw InputError("empty surface");
}

}  // namespace

NormalField filtered_normals(const Surface& s, double sigma, double truncate, double min_support) {
  check_args(s, sigma, truncate);
  const std::size_t nx = s.nx, ny = s.ny, n = nx * ny;
  const Kernel kx = make_kernel(s.dx, sigma, truncate), ky = make_kernel(s.dy, sigma, truncate);
  const double mean = s.valid_mean();
  std::vector<double> v(n), vh(n);
  for (std::size_t i = 0; i < n; ++i) {
    v[i] = s.valid[i] ? 1.0 : 0.0;
    vh[i] = s.valid[i] ? s.z[i] - mean : 0.0;
  }
  // x passes: V with g, g u, g u^2; V h with g, g u.
  std::vector<double> xv0, xv1, xv2, xh0, xh1, tmp;
  correlate(v, xv0, nx, ny, kx.g, kx.half, 0);
  correlate(v, xv1, nx, ny, kx.u, kx.half, 0);
  correlate(v, xv2, nx, ny, kx.u2, kx.half, 0);
  correlate(vh, xh0, nx, ny, kx.g, kx.half, 0);
  correlate(vh, xh1, nx, ny, kx.u, kx.half, 0);
  v.clear();
  vh.clear();
  // y passes: the nine moment images.
  std::vector<double> m00, m01, m02, m10, m11, m20, b00, b01, b10;
  correlate(xv0, m00, nx, ny, ky.g, ky.half, 1);
  correlate(xv0, m01, nx, ny, ky.u, ky.half, 1);
  correlate(xv0, m02, nx, ny, ky.u2, ky.half, 1);
  correlate(xv1, m10, nx, ny, ky.g, ky.half, 1);
  correlate(xv1, m11, nx, ny, ky.u, ky.half, 1);
  correlate(xv2, m20, nx, ny, ky.g, ky.half, 1);
  correlate(xh0, b00, nx, ny, ky.g, ky.half, 1);
  correlate(xh0, b01, nx, ny, ky.u, ky.half, 1);
  correlate(xh1, b10, nx, ny, ky.g, ky.half, 1);

  NormalField f;
  f.nx = nx;
  f.ny = ny;
  f.mx.assign(n, 0.0);
  f.my.assign(n, 0.0);
  f.mz.assign(n, 0.0);
  const double min_mass = min_support * kx.sum * ky.sum;
  std::size_t used = 0, skipped = 0;
#pragma omp parallel for reduction(+ : used, skipped) schedule(static)
  for (long ii = 0; ii < static_cast<long>(n); ++ii) {
    auto i = static_cast<std::size_t>(ii);
    if (!s.valid[i]) continue;  // invalid samples are not elements at all
    double bx, by;
    if (!solve_plane(m00[i], m10[i], m01[i], m20[i], m11[i], m02[i], b00[i], b10[i], b01[i],
                     min_mass, bx, by)) {
      ++skipped;
      continue;
    }
    double m[3];
    set_normal(bx / sigma, by / sigma, m);
    f.mx[i] = m[0];
    f.my[i] = m[1];
    f.mz[i] = m[2];
    ++used;
  }
  f.used = used;
  f.skipped = skipped;
  return f;
}

bool filtered_normal_direct(const Surface& s, std::size_t ix, std::size_t iy, double sigma,
                            double truncate, double min_support, double out[3]) {
  check_args(s, sigma, truncate);
  if (!s.valid[iy * s.nx + ix]) return false;
  const Kernel kx = make_kernel(s.dx, sigma, truncate), ky = make_kernel(s.dy, sigma, truncate);
  // Heights relative to the centre sample (slopes do not depend on the offset; it only keeps
  // the sums well conditioned) so the reference costs just its window.
  const double mean = s.z[iy * s.nx + ix];
  double m00 = 0, m10 = 0, m01 = 0, m20 = 0, m11 = 0, m02 = 0, b00 = 0, b10 = 0, b01 = 0;
  for (long l = -ky.half; l <= ky.half; ++l) {
    long y = static_cast<long>(iy) + l;
    if (y < 0 || y >= static_cast<long>(s.ny)) continue;
    double vv = static_cast<double>(l) * s.dy / sigma;
    double gy = std::exp(-0.5 * vv * vv);
    for (long k = -kx.half; k <= kx.half; ++k) {
      long x = static_cast<long>(ix) + k;
      if (x < 0 || x >= static_cast<long>(s.nx)) continue;
      std::size_t j = static_cast<std::size_t>(y) * s.nx + static_cast<std::size_t>(x);
      if (!s.valid[j]) continue;
      double uu = static_cast<double>(k) * s.dx / sigma;
      double w = std::exp(-0.5 * uu * uu) * gy;
      double h = s.z[j] - mean;
      m00 += w;
      m10 += w * uu;
      m01 += w * vv;
      m20 += w * uu * uu;
      m11 += w * uu * vv;
      m02 += w * vv * vv;
      b00 += w * h;
      b10 += w * h * uu;
      b01 += w * h * vv;
    }
  }
  double bx, by;
  if (!solve_plane(m00, m10, m01, m20, m11, m02, b00, b10, b01, min_support * kx.sum * ky.sum, bx,
                   by))
    return false;
  set_normal(bx / sigma, by / sigma, out);
  return true;
}

}  // namespace microbrdf
