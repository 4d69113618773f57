// Kirchhoff distribution: patch preparation (slopes, aperture, windows) and the direct-summation
// reference of eq. 6 (docs/theory.md §4.1). See include/microbrdf/kirchhoff.hpp.
#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>

#include "microbrdf/error.hpp"
#include "microbrdf/kirchhoff.hpp"

namespace microbrdf {

KirchhoffWindow parse_kirchhoff_window(const std::string& name) {
  if (name == "none") return KirchhoffWindow::None;
  if (name == "hann") return KirchhoffWindow::Hann;
  if (name == "gauss" || name == "gaussian") return KirchhoffWindow::Gauss;
  throw InputError("unknown window '" + name + "' (none | hann | gauss)");
}

std::string to_string(KirchhoffWindow w) {
  switch (w) {
    case KirchhoffWindow::Hann:
      return "hann";
    case KirchhoffWindow::Gauss:
      return "gauss";
    default:
      return "none";
  }
}

namespace {

std::vector<double> window_1d(std::size_t n, KirchhoffWindow w, double gauss_fraction) {
  std::vector<double> v(n, 1.0);
  const double nn = static_cast<double>(n);
  for (std::size_t i = 0; i < n; ++i) {
    double u = (static_cast<double>(i) + 0.5) / nn;  // cell centres in (0, 1)
    if (w == KirchhoffWindow::Hann) {
      double s = std::sin(M_PI * u);
      v[i] = s * s;
    } else if (w == KirchhoffWindow::Gauss) {
      double t = (u - 0.5) / gauss_fraction;
      v[i] = std::exp(-0.5 * t * t);
    }
  }
  return v;
}

}  // namespace

KirchhoffPatch make_kirchhoff_patch(const Surface& s, std::size_t ix0, std::size_t iy0,
                                    std::size_t nx, std::size_t ny, KirchhoffWindow window,
                                    double gauss_fraction) {
  if (nx == 0 || ny == 0 || ix0 + nx > s.nx || iy0 + ny > s.ny)
    throw InputError("Kirchhoff patch outside the surface");
  if (window == KirchhoffWindow::Gauss && !(gauss_fraction > 0))
    throw InputError("Gauss window: the width fraction must be > 0");
  KirchhoffPatch p;
  p.nx = nx;
  p.ny = ny;
  p.dx = s.dx;
  p.dy = s.dy;
  const std::size_t n = nx * ny;
  p.h.assign(n, 0.0);
  p.gx.assign(n, 0.0);
  p.gy.assign(n, 0.0);
  p.w.assign(n, 0.0);
  auto wx = window_1d(nx, window, gauss_fraction), wy = window_1d(ny, window, gauss_fraction);
  auto ok = [&](std::size_t x, std::size_t y) {
    std::size_t i = s.index(x, y);
    return s.valid[i] != 0 && std::isfinite(s.z[i]);
  };
  // Slope along one axis from the valid neighbours (central, one-sided, or none).
  auto slope = [&](std::size_t x, std::size_t y, bool along_x, bool& found) {
    const std::size_t len = along_x ? s.nx : s.ny;
    const std::size_t c = along_x ? x : y;
    const double d = along_x ? s.dx : s.dy;
    auto at = [&](std::size_t k) { return along_x ? s.at(k, y) : s.at(x, k); };
    auto good = [&](std::size_t k) { return along_x ? ok(k, y) : ok(x, k); };
    bool lo = c > 0 && good(c - 1), hi = c + 1 < len && good(c + 1);
    found = lo || hi;
    if (lo && hi) return (at(c + 1) - at(c - 1)) / (2 * d);
    if (hi) return (at(c + 1) - at(c)) / d;
    if (lo) return (at(c) - at(c - 1)) / d;
    return 0.0;
  };
  double sum_w2 = 0;
  for (std::size_t y = 0; y < ny; ++y)
    for (std::size_t x = 0; x < nx; ++x) {
      const std::size_t sx = ix0 + x, sy = iy0 + y, i = y * nx + x;
      if (!ok(sx, sy)) {
        ++p.invalid;
        continue;
      }
      ++p.valid;
      p.h[i] = s.at(sx, sy);
      bool fx = false, fy = false;
      p.gx[i] = slope(sx, sy, true, fx);
      p.gy[i] = slope(sx, sy, false, fy);
      if (!fx || !fy) ++p.no_slope;
      p.w[i] = wx[x] * wy[y];
      sum_w2 += p.w[i] * p.w[i];
    }
  p.area_w2 = sum_w2 * s.dx * s.dy;
  p.valid_area = static_cast<double>(p.valid) * s.dx * s.dy;
  return p;
}

KirchhoffPatch make_kirchhoff_patch(const Surface& s, KirchhoffWindow window,
                                    double gauss_fraction) {
  return make_kirchhoff_patch(s, 0, 0, s.nx, s.ny, window, gauss_fraction);
}

std::complex<double> kirchhoff_amplitude(const KirchhoffPatch& p, const Eigen::Vector3d& q) {
  // exp(-i (q_x x + q_y y)) factorises: per-column and per-row phasors, one sincos per sample
  // for exp(-i q_z h).
  std::vector<std::complex<double>> ex(p.nx), ey(p.ny);
  for (std::size_t x = 0; x < p.nx; ++x)
    ex[x] = std::polar(1.0, -q.x() * p.dx * static_cast<double>(x));
  for (std::size_t y = 0; y < p.ny; ++y)
    ey[y] = std::polar(1.0, -q.y() * p.dy * static_cast<double>(y));
  std::complex<double> total = 0;
  for (std::size_t y = 0; y < p.ny; ++y) {
    std::complex<double> row = 0;
    for (std::size_t x = 0; x < p.nx; ++x) {
      const std::size_t i = y * p.nx + x;
      if (p.w[i] == 0) continue;
      double qm = q.z() - q.x() * p.gx[i] - q.y() * p.gy[i];
      row += (p.w[i] * qm) * std::polar(1.0, -q.z() * p.h[i]) * ex[x];
    }
    total += row * ey[y];
  }
  return total * (p.dx * p.dy);
}

double kirchhoff_dk_direct(const KirchhoffPatch& p, const Eigen::Vector3d& q) {
  if (!(p.area_w2 > 0)) return 0.0;
  return std::norm(kirchhoff_amplitude(p, q)) / (4 * M_PI * M_PI * p.area_w2);
}

Eigen::Vector3d kirchhoff_node_q(std::size_t n, std::size_t ix, std::size_t iy, double lambda_q) {
  const double d = 2.0 / static_cast<double>(n - 1);
  double mx = -1.0 + d * static_cast<double>(ix), my = -1.0 + d * static_cast<double>(iy);
  double r2 = mx * mx + my * my;
  double mz = r2 < 1 ? std::sqrt(1 - r2) : 0.0;
  return (4 * M_PI / lambda_q) * Eigen::Vector3d(mx, my, mz);
}

std::vector<double> kirchhoff_nodes_direct(const KirchhoffPatch& p, double lambda_q,
                                           std::size_t resolution,
                                           const std::vector<std::size_t>& nodes) {
  std::vector<double> out(nodes.size(), 0.0);
  const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(nodes.size());
#pragma omp parallel for schedule(dynamic, 1)
  for (std::ptrdiff_t k = 0; k < count; ++k) {
    std::size_t node = nodes[static_cast<std::size_t>(k)];
    std::size_t ix = node % resolution, iy = node / resolution;
    Eigen::Vector3d q = kirchhoff_node_q(resolution, ix, iy, lambda_q);
    if (!(q.z() > 0)) continue;
    out[static_cast<std::size_t>(k)] = kirchhoff_dk_direct(p, q);
  }
  return out;
}

std::vector<double> bessel_j_all(std::size_t nmax, double x) {
  if (x < 0) throw std::invalid_argument("bessel_j_all: x must be >= 0");
  std::vector<double> j(nmax + 1, 0.0);
  if (x == 0) {
    j[0] = 1;
    return j;
  }
  // Start well above both nmax and x; the recurrence J_{n-1} = (2n/x) J_n - J_{n+1} is stable
  // downwards. Rescale to avoid overflow; normalise with J_0 + 2 sum_{k>=1} J_{2k} = 1.
  std::size_t start = std::max(nmax, static_cast<std::size_t>(x)) + 20 +
                      static_cast<std::size_t>(6 * std::cbrt(x + 1));
  if (start % 2) ++start;
  double jp1 = 0, jn = 1e-300, norm = 0;
  for (std::size_t n = start; n > 0; --n) {
    double jm1 = (2.0 * static_cast<double>(n) / x) * jn - jp1;
    jp1 = jn;
    jn = jm1;  // now J_{n-1}
    std::size_t k = n - 1;
    if (k <= nmax) j[k] = jn;
    if (k > 0 && k % 2 == 0) norm += 2 * jn;
    if (std::fabs(jn) > 1e250) {  // rescale everything so far
      const double s = 1e-250;
      jn *= s;
      jp1 *= s;
      norm *= s;
      for (std::size_t i = k; i <= nmax; ++i) j[i] *= s;
    }
  }
  norm += jn;  // J_0
  for (double& v : j) v /= norm;
  return j;
}

}  // namespace microbrdf
