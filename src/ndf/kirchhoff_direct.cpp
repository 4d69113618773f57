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

KirchhoffIntegration parse_kirchhoff_integration(const std::string& name) {
  if (name == "exact") return KirchhoffIntegration::Exact;
  if (name == "midpoint") return KirchhoffIntegration::Midpoint;
  throw InputError("unknown D_K integration '" + name + "' (exact | midpoint)");
}

std::string to_string(KirchhoffIntegration m) {
  return m == KirchhoffIntegration::Exact ? "exact" : "midpoint";
}

namespace {

using cd = std::complex<double>;

// sinh(u)/u (sin(t)/t for u = i t), by its series where |u| is small.
cd sinhc(cd u) {
  if (std::abs(u) < 1e-3) return 1.0 + u * u / 6.0;
  return std::sinh(u) / u;
}

// exp[x, y] = (e^y - e^x)/(y - x) = e^{(x+y)/2} sinhc((y-x)/2).
cd exp_dd2(cd x, cd y) { return std::exp(0.5 * (x + y)) * sinhc(0.5 * (y - x)); }

}  // namespace

std::complex<double> exp_divided_difference(std::complex<double> z0, std::complex<double> z1,
                                            std::complex<double> z2) {
  // Shift invariance: exp[z + c] = e^c exp[z]. About the mean m the deviations d_k sum to 0, so
  // the complete homogeneous polynomials obey h_n = -e2 h_{n-2} + e3 h_{n-3} (e1 = 0), and
  // exp[d0, d1, d2] = sum_n h_n(d) / (n + 2)!  (docs/kirchhoff.md eq. K3).
  const cd m = (z0 + z1 + z2) / 3.0;
  const cd d0 = z0 - m, d1 = z1 - m, d2 = z2 - m;
  const double r = std::max({std::abs(d0), std::abs(d1), std::abs(d2)});
  if (r < 1.0) {
    const cd e2 = d0 * d1 + d0 * d2 + d1 * d2, e3 = d0 * d1 * d2;
    cd h2 = 1.0, h1 = 0.0, h0 = -e2;  // h_{n-2}, h_{n-1}, h_n at n = 2; h_0 = 1, h_1 = 0
    cd sum = 0.5;                     // h_0 / 2!
    double fact = 24;                 // (n + 2)! at n = 2
    // |h_n| <= (n+1)(n+2)/2 r^n: 22 terms leave < 1e-21 (a fixed count; odd h_n can vanish).
    for (int n = 2; n < 24; ++n) {
      sum += h0 / fact;
      const cd next = -e2 * h1 + e3 * h2;  // h_{n+1}
      h2 = h1;
      h1 = h0;
      h0 = next;
      fact *= static_cast<double>(n + 3);
    }
    return std::exp(m) * sum;
  }
  // Otherwise the two points furthest apart (a, b; c the third) are at least 1.5 apart:
  // exp[a, b, c] = (exp[a, c] - exp[b, c]) / (a - b) loses at most a few digits.
  cd a = z0, b = z1, c = z2;
  const double s01 = std::abs(z0 - z1), s02 = std::abs(z0 - z2), s12 = std::abs(z1 - z2);
  if (s02 >= s01 && s02 >= s12) {
    b = z2;
    c = z1;
  } else if (s12 >= s01 && s12 >= s02) {
    a = z1;
    b = z2;
    c = z0;
  }
  return (exp_dd2(a, c) - exp_dd2(b, c)) / (a - b);
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
  // The triangles of the piecewise-linear surface (exact integration): window weight = mean of
  // the vertices' weights.
  double sum_tri = 0;
  for (std::size_t y = 0; y + 1 < ny; ++y)
    for (std::size_t x = 0; x + 1 < nx; ++x) {
      const std::size_t i00 = y * nx + x, i10 = i00 + 1, i01 = i00 + nx, i11 = i01 + 1;
      for (const std::size_t third : {i10, i01}) {
        if (p.w[i00] == 0 || p.w[i11] == 0 || p.w[third] == 0) continue;
        const double wt = (p.w[i00] + p.w[i11] + p.w[third]) / 3;
        sum_tri += wt * wt;
        ++p.triangles;
      }
    }
  p.area_w2_tri = 0.5 * sum_tri * s.dx * s.dy;
  p.valid_area_tri = 0.5 * static_cast<double>(p.triangles) * s.dx * s.dy;
  return p;
}

KirchhoffPatch make_kirchhoff_patch(const Surface& s, KirchhoffWindow window,
                                    double gauss_fraction) {
  return make_kirchhoff_patch(s, 0, 0, s.nx, s.ny, window, gauss_fraction);
}

double kirchhoff_area_w2(const KirchhoffPatch& p, KirchhoffIntegration m) {
  return m == KirchhoffIntegration::Exact ? p.area_w2_tri : p.area_w2;
}

namespace {

// Eq. K1 summed over the triangles: I(q) = sum_T w_T (q.m_T) dx dy exp[z_0, z_1, z_2], with
// exp[z_0, z_1, z_2] = e^{z_0} exp[0, z_1 - z_0, z_2 - z_0] and the differences formed from the
// edge vectors (no cancellation of large phases).
std::complex<double> amplitude_exact(const KirchhoffPatch& p, const Eigen::Vector3d& q) {
  const std::size_t nx = p.nx, ny = p.ny;
  if (nx < 2 || ny < 2) return 0.0;
  const double ex = q.x() * p.dx, ey = q.y() * p.dy;  // phase steps along the cell edges
  std::complex<double> total = 0;
  for (std::size_t y = 0; y + 1 < ny; ++y) {
    std::complex<double> row = 0;
    for (std::size_t x = 0; x + 1 < nx; ++x) {
      const std::size_t i00 = y * nx + x, i10 = i00 + 1, i01 = i00 + nx, i11 = i01 + 1;
      if (p.w[i00] == 0 || p.w[i11] == 0) continue;
      const double h00 = p.h[i00], h11 = p.h[i11];
      const cd z0 = cd(0, -(q.x() * p.dx * static_cast<double>(x) + q.z() * h00));
      // Lower triangle (00, 10, 11) and upper triangle (00, 11, 01).
      if (p.w[i10] != 0) {
        const double h10 = p.h[i10];
        const double gx = (h10 - h00) / p.dx, gy = (h11 - h10) / p.dy;
        const double wt = (p.w[i00] + p.w[i10] + p.w[i11]) / 3;
        const cd u(0, -(ex + q.z() * (h10 - h00))), v(0, -(ex + ey + q.z() * (h11 - h00)));
        row += wt * (q.z() - q.x() * gx - q.y() * gy) * exp_divided_difference(z0, z0 + u, z0 + v);
      }
      if (p.w[i01] != 0) {
        const double h01 = p.h[i01];
        const double gx = (h11 - h01) / p.dx, gy = (h01 - h00) / p.dy;
        const double wt = (p.w[i00] + p.w[i01] + p.w[i11]) / 3;
        const cd u(0, -(ex + ey + q.z() * (h11 - h00))), v(0, -(ey + q.z() * (h01 - h00)));
        row += wt * (q.z() - q.x() * gx - q.y() * gy) * exp_divided_difference(z0, z0 + u, z0 + v);
      }
    }
    total += row * std::polar(1.0, -q.y() * p.dy * static_cast<double>(y));
  }
  return total * (p.dx * p.dy);
}

}  // namespace

std::complex<double> kirchhoff_amplitude(const KirchhoffPatch& p, const Eigen::Vector3d& q,
                                         KirchhoffIntegration m) {
  if (m == KirchhoffIntegration::Exact) return amplitude_exact(p, q);
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

double kirchhoff_dk_direct(const KirchhoffPatch& p, const Eigen::Vector3d& q,
                           KirchhoffIntegration m) {
  const double a = kirchhoff_area_w2(p, m);
  if (!(a > 0)) return 0.0;
  return std::norm(kirchhoff_amplitude(p, q, m)) / (4 * M_PI * M_PI * a);
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
                                           const std::vector<std::size_t>& nodes,
                                           KirchhoffIntegration m) {
  std::vector<double> out(nodes.size(), 0.0);
  const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(nodes.size());
#pragma omp parallel for schedule(dynamic, 1)
  for (std::ptrdiff_t k = 0; k < count; ++k) {
    std::size_t node = nodes[static_cast<std::size_t>(k)];
    std::size_t ix = node % resolution, iy = node / resolution;
    Eigen::Vector3d q = kirchhoff_node_q(resolution, ix, iy, lambda_q);
    if (!(q.z() > 0)) continue;
    out[static_cast<std::size_t>(k)] = kirchhoff_dk_direct(p, q, m);
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
