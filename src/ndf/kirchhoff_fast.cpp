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

template <class Transform>
std::vector<double> table_fast(const KirchhoffPatch& p, double lambda_q, std::size_t resolution,
                               double accuracy, KirchhoffFastInfo* info) {
  if (!(lambda_q > 0)) throw InputError("Kirchhoff: lambda_q must be > 0");
  if (resolution < 3) throw InputError("Kirchhoff: resolution must be >= 3");
  if (!(accuracy > 0 && accuracy < 1)) throw InputError("Kirchhoff: accuracy must be in (0, 1)");
  const std::size_t N = resolution, nx = p.nx, ny = p.ny;
  std::vector<double> out(N * N, 0.0);
  if (!(p.area_w2 > 0)) return out;

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
  if (info) {
    info->terms = terms;
    info->height_half_range = H;
    info->z_max = zmax;
    info->tail_bound = tail;
  }
  BesselTable bt(terms, zmax);

  // Per-sample constants.
  const std::size_t ns = nx * ny;
  const bool big = ns + N * N > (1u << 17);  // threads only pay off on large problems
  std::vector<cd> base(ns);
  std::vector<double> zs(ns);
  for (std::size_t i = 0; i < ns; ++i) {
    double hp = p.w[i] != 0 ? p.h[i] - hc : 0.0;
    base[i] = std::polar(p.w[i] * p.dx * p.dy, -qc * hp);
    zs[i] = r * hp;
  }

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
  std::vector<cd> in(3 * ns), xo(3 * ny * N), ym(N * N), yc(N * N), b1(N * N), b2(N * N);
  const cd mi[4] = {cd(1, 0), cd(0, -1), cd(-1, 0), cd(0, 1)};  // (-i)^n

  for (std::size_t nn = terms; nn-- > 0;) {
    const std::size_t n = nn;
    // Sample arrays of term n.
#pragma omp parallel for schedule(static) if (big)
    for (std::size_t i = 0; i < ns; ++i) {
      if (p.w[i] == 0) {
        in[i] = in[ns + i] = in[2 * ns + i] = 0.0;
        continue;
      }
      double z = zs[i], a = std::fabs(z);
      auto cj = [&](std::size_t k) {  // c_k(z) = (k ? 2 : 1) (-i)^k J_k(z), J_k(-a) = (-1)^k J_k(a)
        double j = bt(k, a);
        if (z < 0 && (k & 1)) j = -j;
        return (k ? 2.0 : 1.0) * j * mi[k & 3];
      };
      cd cn = cj(n), cp = cj(n + 1);
      cd s = n == 0 ? 0.5 * cp : (n == 1 ? cj(0) + 0.5 * cp : 0.5 * (cj(n - 1) + cp));
      cd b = base[i];
      in[i] = b * (qc * cn + r * s);
      in[ns + i] = b * (p.gx[i] * cn);
      in[2 * ns + i] = b * (p.gy[i] * cn);
    }
    // x-pass, written transposed: xo[k * 3ny + (component * ny + y)], k = q_x index.
    const std::size_t bt = 3 * ny;
    czx.execute(in.data(), nx, 1, xo.data(), 1, bt);
#pragma omp parallel for schedule(static) if (big)
    for (std::size_t k = 0; k < N; ++k) {
      cd* col = xo.data() + k * bt;
      for (std::size_t y = 0; y < ny; ++y) col[y] -= qx[k] * col[ny + y];
    }
    czy.execute(xo.data(), bt, 1, ym.data());  // column k -> ym[k * N + l], l = q_y index
    czy.execute(xo.data() + 2 * ny, bt, 1, yc.data());
    // Clenshaw step: b_n = I_n + 2 t b_{n+1} - b_{n+2}; at n = 0: f = I_0 + t b_1 - b_2.
    const double two = n == 0 ? 1.0 : 2.0;
#pragma omp parallel for schedule(static) if (big)
    for (std::size_t k = 0; k < N; ++k)
      for (std::size_t l = 0; l < N; ++l) {
        const std::size_t j = k * N + l;
        double t = tnode[j];
        if (std::isnan(t)) continue;
        cd in_n = ym[j] - qy[l] * yc[j];
        cd bn = in_n + two * t * b1[j] - b2[j];
        b2[j] = b1[j];
        b1[j] = bn;
      }
  }
  const double norm = 1.0 / (4 * M_PI * M_PI * p.area_w2);
  for (std::size_t k = 0; k < N; ++k)
    for (std::size_t l = 0; l < N; ++l)
      if (!std::isnan(tnode[k * N + l])) out[l * N + k] = std::norm(b1[k * N + l]) * norm;
  return out;
}

}  // namespace

std::vector<double> kirchhoff_table_fast(const KirchhoffPatch& p, double lambda_q,
                                         std::size_t resolution, double accuracy,
                                         KirchhoffFastInfo* info, bool chirp_z) {
  return chirp_z ? table_fast<detail::ChirpZ>(p, lambda_q, resolution, accuracy, info)
                 : table_fast<detail::ZoomNufft>(p, lambda_q, resolution, accuracy, info);
}

}  // namespace microbrdf
