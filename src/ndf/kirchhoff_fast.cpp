// Kirchhoff distribution on the full N x N table at fixed lambda_q, fast (docs/theory.md §4.3).
//
// On the table q = |q| (m_x, m_y, m_z) and q_z = |q| m_z runs over [0, |q|]. Write
// q_z = q_c + r t, q_c = r = |q|/2, t in [-1, 1], and h' = h - h_c (h_c the middle of the height
// range, H its half-width). Jacobi-Anger gives, exactly,
//   exp(-i q_z h') = exp(-i q_c h') sum_n c_n(r h') T_n(t),  c_0 = J_0, c_n = 2 (-i)^n J_n,
// and q_z exp(-i q_z h') has the coefficients q_c C_n + r S_n (t T_n = (T_{n+1} + T_{|n-1|})/2).
// |J_n(r h')| <= |J_n(r H)| for n >= r H, so the series is cut where 2 sum |J_n(r H)| < accuracy.
// Per term n the three sample arrays
//   A_n = w (q_c C_n + r S_n),  B_n = w g_x C_n,  C_n' = w g_y C_n   (times dx dy)
// go through a chirp-z transform along x (exact q_x of the nodes), A_n - q_x B_n and C_n' through
// one along y, and I_n = Y[A_n - q_x B_n] - q_y Y[C_n']; I(q) = sum_n I_n T_n(t(q)) by Clenshaw.
// The global phase exp(-i q_z h_c) and the patch origin are dropped (|I| is unchanged).
#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <stdexcept>
#include <type_traits>

#include "core/fft.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/kirchhoff.hpp"

namespace microbrdf {
namespace {

using cd = std::complex<double>;

// J_n(z) for n = 0..nmax, z in [0, zmax], by cubic Hermite interpolation of a table (spacing
// 1/32, derivatives from J_n' = (J_{n-1} - J_{n+1})/2): error < 3e-9.
class BesselTable {
 public:
  BesselTable(std::size_t nmax, double zmax) : nmax_(nmax), step_(1.0 / 32) {
    npts_ = static_cast<std::size_t>(std::ceil(zmax / step_)) + 2;
    val_.assign((nmax + 1) * npts_, 0.0);
    der_.assign((nmax + 1) * npts_, 0.0);
    for (std::size_t i = 0; i < npts_; ++i) {
      auto j = bessel_j_all(nmax + 1, step_ * static_cast<double>(i));
      for (std::size_t n = 0; n <= nmax; ++n) {
        val_[n * npts_ + i] = j[n];
        der_[n * npts_ + i] = n == 0 ? -j[1] : 0.5 * (j[n - 1] - j[n + 1]);
      }
    }
  }
  double operator()(std::size_t n, double z) const {  // z >= 0
    double f = z / step_;
    auto i = std::min(static_cast<std::size_t>(f), npts_ - 2);
    double u = f - static_cast<double>(i);
    const double* v = &val_[n * npts_ + i];
    const double* d = &der_[n * npts_ + i];
    double u2 = u * u, u3 = u2 * u;
    return (2 * u3 - 3 * u2 + 1) * v[0] + (u3 - 2 * u2 + u) * step_ * d[0] +
           (-2 * u3 + 3 * u2) * v[1] + (u3 - u2) * step_ * d[1];
  }

 private:
  std::size_t nmax_, npts_ = 0;
  double step_;
  std::vector<double> val_, der_;
};

}  // namespace

namespace {

// Gauss-Legendre nodes and weights on [0, 1] (Newton on P_n from the Chebyshev guesses).
void gauss_legendre01(std::size_t n, std::vector<double>& x, std::vector<double>& w) {
  x.assign(n, 0.0);
  w.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    double t = std::cos(M_PI * (static_cast<double>(i) + 0.75) / (static_cast<double>(n) + 0.5));
    double dp = 1;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1, p1 = t;  // P_0, P_1
      for (std::size_t k = 2; k <= n; ++k) {
        const double p2 =
            ((2.0 * static_cast<double>(k) - 1) * t * p1 - (static_cast<double>(k) - 1) * p0) /
            static_cast<double>(k);
        p0 = p1;
        p1 = p2;
      }
      dp = static_cast<double>(n) * (t * p1 - p0) / (t * t - 1);
      const double dt = p1 / dp;
      t -= dt;
      if (std::fabs(dt) < 1e-16) break;
    }
    x[i] = 0.5 * (1 - t);
    w[i] = 1.0 / ((1 - t * t) * dp * dp);  // 2 / ((1 - t^2) P_n'^2), halved for [0, 1]
  }
}

// One position of the triangle rule: cell coordinates (a, b) in [0, 1]^2 of a point of the
// lower (family 0: b <= a) or upper (family 1: a <= b) triangle of every cell, and its weight
// (the weights of one family sum to 1/2, the triangle's area in cell units).
struct RulePoint {
  double a, b, weight;
};

// Collapsed (Duffy) Gauss-Legendre rule, pu points along the collapsed direction and pv across,
// grouped by b (points of one group share their y offset, hence one y-pass).
std::vector<std::vector<RulePoint>> triangle_rule(int family, std::size_t pu, std::size_t pv) {
  std::vector<double> xu, wu, xv, wv;
  gauss_legendre01(pu, xu, wu);
  gauss_legendre01(pv, xv, wv);
  std::vector<std::vector<RulePoint>> groups(pv);
  for (std::size_t j = 0; j < pv; ++j)
    for (std::size_t i = 0; i < pu; ++i) {
      const double v = xv[j], u = xu[i];
      if (family == 0)  // b = v, a in [v, 1]
        groups[j].push_back({v + (1 - v) * u, v, wu[i] * wv[j] * (1 - v)});
      else  // b = v, a in [0, v]
        groups[j].push_back({v * u, v, wu[i] * wv[j] * v});
    }
  return groups;
}

// Relative error of the p-point Gauss-Legendre rule for exp(i w t) on [0, 1], |w| <= span:
// (p!)^4 / ((2p + 1) ((2p)!)^3) span^(2p).
double gauss_error(std::size_t p, double span) {
  double lg = 4 * std::lgamma(static_cast<double>(p) + 1) -
              std::log(2.0 * static_cast<double>(p) + 1) -
              3 * std::lgamma(2.0 * static_cast<double>(p) + 1) +
              2.0 * static_cast<double>(p) * std::log(std::max(span, 1e-300));
  return std::exp(lg);
}

template <class Transform>
std::vector<double> table_fast(const KirchhoffPatch& p, double lambda_q, std::size_t resolution,
                               double accuracy, KirchhoffFastInfo* info,
                               KirchhoffIntegration method, double band_x, double band_y) {
  if (!(lambda_q > 0)) throw InputError("Kirchhoff: lambda_q must be > 0");
  if (resolution < 3) throw InputError("Kirchhoff: resolution must be >= 3");
  if (!(accuracy > 0 && accuracy < 1)) throw InputError("Kirchhoff: accuracy must be in (0, 1)");
  const bool exact = method == KirchhoffIntegration::Exact;
  const std::size_t N = resolution;
  std::vector<double> out(N * N, 0.0);
  const double area = kirchhoff_area_w2(p, method);
  if (!(area > 0)) return out;
  // The transforms run over the samples (midpoint) or the cells (exact: one rule point each).
  const std::size_t nx = exact ? p.nx - 1 : p.nx, ny = exact ? p.ny - 1 : p.ny;

  const double qmag = 4 * M_PI / lambda_q, delta = 2.0 / static_cast<double>(N - 1);
  const double qc = 0.5 * qmag, r = 0.5 * qmag;
  double hmin = INFINITY, hmax = -INFINITY;
  for (std::size_t i = 0; i < p.h.size(); ++i)
    if (p.w[i] != 0) {
      hmin = std::min(hmin, p.h[i]);
      hmax = std::max(hmax, p.h[i]);
    }
  const double hc = 0.5 * (hmin + hmax), H = 0.5 * (hmax - hmin), zmax = r * H;

  // Number of terms: the smallest count whose dropped tail 2 sum_{n >= terms} |J_n(zmax)| is
  // below `accuracy` (terms >= zmax, where |J_n| grows monotonically in z up to zmax).
  std::size_t guess = static_cast<std::size_t>(zmax + 10 * std::cbrt(zmax + 1) + 40);
  auto jz = bessel_j_all(guess, zmax);
  std::size_t terms = 1;
  double tail = 0;
  for (std::size_t n = guess; n >= 1; --n) {
    double t = tail + 2 * std::fabs(jz[n]);
    if (t > accuracy || static_cast<double>(n) < zmax) {
      terms = n + 1;
      break;
    }
    tail = t;
  }
  // The q_z factor makes the A series one degree longer (q_z T_{terms-1} has a T_terms part).
  ++terms;
  BesselTable bt(terms, zmax);

  // Per-family cell data of the triangles (exact) or the samples themselves (midpoint): height
  // relative to h_c at the cell origin, height steps along a and b (slope x spacing), slopes and
  // the window weight (0 = no triangle).
  const std::size_t ns = nx * ny;
  struct Family {
    std::vector<double> h0, sa, sb, gx, gy, w;
  };
  std::vector<Family> fam(exact ? 2 : 1);
  double longest = 0;  // largest phase span of a valid triangle's edge, rad
  const double bx = std::min(qmag, band_x), by = std::min(qmag, band_y);
  for (auto& f : fam) {
    f.h0.assign(ns, 0.0);
    f.gx.assign(ns, 0.0);
    f.gy.assign(ns, 0.0);
    f.w.assign(ns, 0.0);
    if (exact) {
      f.sa.assign(ns, 0.0);
      f.sb.assign(ns, 0.0);
    }
  }
  if (!exact) {
    for (std::size_t i = 0; i < ns; ++i)
      if (p.w[i] != 0) {
        fam[0].h0[i] = p.h[i] - hc;
        fam[0].gx[i] = p.gx[i];
        fam[0].gy[i] = p.gy[i];
        fam[0].w[i] = p.w[i];
      }
  } else {
    for (std::size_t y = 0; y < ny; ++y)
      for (std::size_t x = 0; x < nx; ++x) {
        const std::size_t c = y * nx + x, i00 = y * p.nx + x, i10 = i00 + 1, i01 = i00 + p.nx,
                          i11 = i01 + 1;
        if (p.w[i00] == 0 || p.w[i11] == 0) continue;
        const double h00 = p.h[i00], h11 = p.h[i11];
        for (int k = 0; k < 2; ++k) {
          const std::size_t i3 = k == 0 ? i10 : i01;  // lower (00,10,11), upper (00,11,01)
          if (p.w[i3] == 0) continue;
          const double h3 = p.h[i3];
          const double sa = k == 0 ? h3 - h00 : h11 - h3, sb = k == 0 ? h11 - h3 : h3 - h00;
          Family& f = fam[static_cast<std::size_t>(k)];
          f.h0[c] = h00 - hc;
          f.sa[c] = sa;
          f.sb[c] = sb;
          f.gx[c] = sa / p.dx;
          f.gy[c] = sb / p.dy;
          f.w[c] = (p.w[i00] + p.w[i11] + p.w[i3]) / 3;
          // Largest phase difference along an edge over the nodes that count: |q| x its
          // length, or with |q_x| <= bx, |q_y| <= by (a band mask) bx |dx| + by |dy| + |q| |dh|.
          const double d11 = std::fabs(h11 - h00);
          const double ea = std::min(qmag * std::hypot(p.dx, sa), bx * p.dx + qmag * std::fabs(sa)),
                       eb = std::min(qmag * std::hypot(p.dy, sb), by * p.dy + qmag * std::fabs(sb)),
                       ed = std::min(qmag * std::sqrt(p.dx * p.dx + p.dy * p.dy + d11 * d11),
                                     bx * p.dx + by * p.dy + qmag * d11);
          longest = std::max({longest, ea, eb, ed});
        }
      }
  }
  // Rule: one point at the sample (midpoint), or per triangle a collapsed Gauss-Legendre rule
  // whose error for the largest phase span along an edge is below accuracy / 100.
  const double span = longest;
  std::size_t pu = 1;
  if (exact)
    while (pu < 40 && gauss_error(pu, span) > accuracy * 1e-2) ++pu;
  const std::size_t pv = exact ? pu + 1 : 1;
  std::vector<std::vector<std::vector<RulePoint>>> rules(fam.size());
  for (std::size_t f = 0; f < fam.size(); ++f)
    rules[f] = exact ? triangle_rule(static_cast<int>(f), pu, pv)
                     : std::vector<std::vector<RulePoint>>{{{0.0, 0.0, 1.0}}};
  if (info) {
    info->terms = terms;
    info->height_half_range = H;
    info->z_max = zmax;
    info->tail_bound = tail;
    info->points_per_triangle = pu * pv;
    info->phase_span = span;
  }

  const bool big = ns + N * N > (1u << 17);  // threads only pay off on large problems
  // Node tables: t(q_z) per node (NaN outside the disk), q_x per column, q_y per row.
  std::vector<double> tnode(N * N, NAN), qx(N), qy(N);
  for (std::size_t k = 0; k < N; ++k)
    qx[k] = qy[k] = qmag * (-1.0 + delta * static_cast<double>(k));
  for (std::size_t iy = 0; iy < N; ++iy)
    for (std::size_t ix = 0; ix < N; ++ix) {
      double mx = qx[ix] / qmag, my = qy[iy] / qmag, rr = mx * mx + my * my;
      if (rr < 1) tnode[ix * N + iy] = (qmag * std::sqrt(1 - rr) - qc) / r;
    }

  // Transforms: exact chirp-z, or the NUFFT with taps for accuracy / 100 relative to sum |x|.
  auto make = [&](std::size_t n, double d, std::size_t batch) {
    if constexpr (std::is_same_v<Transform, detail::ChirpZ>)
      return std::make_unique<Transform>(n, N, -qmag * d, qmag * delta * d, batch);
    else
      return std::make_unique<Transform>(n, N, -qmag * d, qmag * delta * d, batch,
                                         Transform::taps_for(accuracy * 1e-2));
  };
  auto czx_p = make(nx, p.dx, 3 * ny);
  auto czy_p = make(ny, p.dy, N);
  Transform& czx = *czx_p;
  Transform& czy = *czy_p;
  const std::size_t bt3 = 3 * ny;
  std::vector<cd> in(3 * ns), xo(bt3 * N), ym(N * N), yc(N * N), b1(N * N), b2(N * N);
  std::vector<cd> xacc, it;  // exact: sums over the rule points
  if (exact) {
    xacc.resize(bt3 * N);
    it.resize(N * N);
  }
  const cd mi[4] = {cd(1, 0), cd(0, -1), cd(-1, 0), cd(0, 1)};  // (-i)^n
  const double dA = p.dx * p.dy;

  for (std::size_t nn = terms; nn-- > 0;) {
    const std::size_t n = nn;
    if (exact) std::fill(it.begin(), it.end(), cd(0));
    for (std::size_t f = 0; f < fam.size(); ++f) {
      const Family& F = fam[f];
      for (const auto& group : rules[f]) {
        cd* xsum = exact ? xacc.data() : xo.data();
        if (exact) std::fill(xacc.begin(), xacc.end(), cd(0));
        for (const RulePoint& rp : group) {
          // Sample arrays of term n at this rule point.
#pragma omp parallel for schedule(static) if (big)
          for (std::size_t i = 0; i < ns; ++i) {
            if (F.w[i] == 0) {
              in[i] = in[ns + i] = in[2 * ns + i] = 0.0;
              continue;
            }
            const double hp = exact ? F.h0[i] + rp.a * F.sa[i] + rp.b * F.sb[i] : F.h0[i];
            const double z = r * hp, a = std::fabs(z);
            auto cj = [&](std::size_t k) {  // c_k(z) = (k ? 2 : 1) (-i)^k J_k(z)
              double j = bt(k, a);
              if (z < 0 && (k & 1)) j = -j;
              return (k ? 2.0 : 1.0) * j * mi[k & 3];
            };
            cd cn = cj(n), cp = cj(n + 1);
            cd s = n == 0 ? 0.5 * cp : (n == 1 ? cj(0) + 0.5 * cp : 0.5 * (cj(n - 1) + cp));
            const cd b = std::polar(F.w[i] * rp.weight * dA, -qc * hp);
            in[i] = b * (qc * cn + r * s);
            in[ns + i] = b * (F.gx[i] * cn);
            in[2 * ns + i] = b * (F.gy[i] * cn);
          }
          // x-pass, written transposed: xo[k * 3ny + (component * ny + y)], k = q_x index.
          czx.execute(in.data(), nx, 1, xo.data(), 1, bt3);
          if (exact) {  // shift by the rule point's x offset: a phase per q_x
            const double ox = rp.a * p.dx;
#pragma omp parallel for schedule(static) if (big)
            for (std::size_t k = 0; k < N; ++k) {
              const cd ph = std::polar(1.0, -qx[k] * ox);
              cd* dst = xacc.data() + k * bt3;
              const cd* src = xo.data() + k * bt3;
              for (std::size_t j = 0; j < bt3; ++j) dst[j] += ph * src[j];
            }
          }
        }
#pragma omp parallel for schedule(static) if (big)
        for (std::size_t k = 0; k < N; ++k) {
          cd* col = xsum + k * bt3;
          for (std::size_t y = 0; y < ny; ++y) col[y] -= qx[k] * col[ny + y];
        }
        czy.execute(xsum, bt3, 1, ym.data());  // column k -> ym[k * N + l], l = q_y index
        czy.execute(xsum + 2 * ny, bt3, 1, yc.data());
        if (exact) {  // shift by the group's y offset, sum the q_y part in
          const double oy = group.front().b * p.dy;
#pragma omp parallel for schedule(static) if (big)
          for (std::size_t l = 0; l < N; ++l) {
            const cd ph = std::polar(1.0, -qy[l] * oy);
            for (std::size_t k = 0; k < N; ++k) {
              const std::size_t j = k * N + l;
              it[j] += ph * (ym[j] - qy[l] * yc[j]);
            }
          }
        }
      }
    }
    // Clenshaw step: b_n = I_n + 2 t b_{n+1} - b_{n+2}; at n = 0: f = I_0 + t b_1 - b_2.
    const double two = n == 0 ? 1.0 : 2.0;
#pragma omp parallel for schedule(static) if (big)
    for (std::size_t k = 0; k < N; ++k)
      for (std::size_t l = 0; l < N; ++l) {
        const std::size_t j = k * N + l;
        double t = tnode[j];
        if (std::isnan(t)) continue;
        cd in_n = exact ? it[j] : ym[j] - qy[l] * yc[j];
        cd bn = in_n + two * t * b1[j] - b2[j];
        b2[j] = b1[j];
        b1[j] = bn;
      }
  }
  const double norm = 1.0 / (4 * M_PI * M_PI * area);
  for (std::size_t k = 0; k < N; ++k)
    for (std::size_t l = 0; l < N; ++l)
      if (!std::isnan(tnode[k * N + l])) out[l * N + k] = std::norm(b1[k * N + l]) * norm;
  return out;
}

}  // namespace

std::vector<double> kirchhoff_table_fast(const KirchhoffPatch& p, double lambda_q,
                                         std::size_t resolution, double accuracy,
                                         KirchhoffFastInfo* info, bool chirp_z,
                                         KirchhoffIntegration m, double band_x, double band_y) {
  return chirp_z ? table_fast<detail::ChirpZ>(p, lambda_q, resolution, accuracy, info, m, band_x,
                                              band_y)
                 : table_fast<detail::ZoomNufft>(p, lambda_q, resolution, accuracy, info, m, band_x,
                                                 band_y);
}

}  // namespace microbrdf
