// Real spherical harmonics by the normalised associated-Legendre recurrence (docs/theory.md §6.1)
// and the odd-completion basis (docs/theory.md §6.2). See include/microbrdf/sh_basis.hpp.
#include "microbrdf/sh_basis.hpp"

#include <algorithm>
#include <cmath>
#include <new>
#include <string>
#include <vector>

#include "microbrdf/error.hpp"
#include "microbrdf/quadrature.hpp"

namespace microbrdf {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Recurrence coefficients up to kShMaxL, computed once (a function-local static is initialised
// thread-safely). Indexed by tri(l, m) = l (l + 1) / 2 + m, m <= l.
struct Tables {
  std::vector<double> a, b;  // a_lm, b_lm of docs/theory.md §6.1 (l >= m + 2)
  std::vector<double> diag;  // sqrt((2m+1)/(2m)): Pbar_m^m from Pbar_{m-1}^{m-1}
  std::vector<double> sub;   // sqrt(2m+3): Pbar_{m+1}^m from Pbar_m^m
  Tables() {
    const int n = (kShMaxL + 1) * (kShMaxL + 2) / 2;
    a.assign(n, 0.0);
    b.assign(n, 0.0);
    for (int l = 2; l <= kShMaxL; ++l)
      for (int m = 0; m + 2 <= l; ++m) {
        const double ll = l, mm = m;
        a[l * (l + 1) / 2 + m] = std::sqrt((4 * ll * ll - 1) / (ll * ll - mm * mm));
        b[l * (l + 1) / 2 + m] =
            std::sqrt(((ll - 1) * (ll - 1) - mm * mm) / (4 * (ll - 1) * (ll - 1) - 1));
      }
    diag.assign(kShMaxL + 1, 0.0);
    sub.assign(kShMaxL + 1, 0.0);
    for (int m = 0; m <= kShMaxL; ++m) {
      diag[m] = m == 0 ? 0.0 : std::sqrt((2.0 * m + 1) / (2.0 * m));
      sub[m] = std::sqrt(2.0 * m + 3);
    }
  }
};

const Tables& tables() {
  static const Tables t;
  return t;
}

void check_lmax(int lmax, int lo) {
  if (lmax < lo || lmax > kShMaxL)
    throw InputError("spherical harmonics: lmax " + std::to_string(lmax) + " outside [" +
                     std::to_string(lo) + ", " + std::to_string(kShMaxL) + "]");
}

// Evaluates all Y_lm (Odd = false: into out[l^2 + l + m]) or only those with l + m odd
// (Odd = true: into out[sh_odd_index(l, m)]). The cost is the same O(lmax^2) recurrence either
// way; the odd variant skips the trigonometric products of the dropped half.
template <bool Odd>
void eval_core(int lmax, const Vec3& w, double* out) {
  const Tables& t = tables();
  const double rho = std::hypot(w.x(), w.y());
  const double r = std::hypot(rho, w.z());
  double x = 1, s = 0, cphi = 1, sphi = 0;  // pole (or zero vector): theta = 0, phi = 0
  if (r > 0) {
    x = w.z() / r;
    s = rho / r;
  }
  if (rho > 0) {
    cphi = w.x() / rho;
    sphi = w.y() / rho;
  }
  constexpr double kSqrt2 = 1.41421356237309504880;
  double pmm = 1 / std::sqrt(4 * kPi);  // Pbar_m^m
  double cm = 1, sm = 0;                // cos(m phi), sin(m phi)
  for (int m = 0; m <= lmax; ++m) {
    if (m > 0) {
      pmm *= t.diag[m] * s;
      const double c = cm * cphi - sm * sphi;
      sm = sm * cphi + cm * sphi;
      cm = c;
    }
    const double fc = m == 0 ? 1.0 : kSqrt2 * cm, fs = kSqrt2 * sm;
    auto put = [&](int l, double p) {
      if constexpr (Odd) {
        if (((l + m) & 1) == 0) return;
        out[sh_odd_index(l, m)] = p * fc;
        if (m > 0) out[sh_odd_index(l, -m)] = p * fs;
      } else {
        out[l * l + l + m] = p * fc;
        if (m > 0) out[l * l + l - m] = p * fs;
      }
    };
    put(m, pmm);
    if (m + 1 > lmax) break;
    double p0 = pmm, p1 = t.sub[m] * x * pmm;
    put(m + 1, p1);
    for (int l = m + 2; l <= lmax; ++l) {
      const int i = l * (l + 1) / 2 + m;
      const double p = t.a[i] * (x * p1 - t.b[i] * p0);
      put(l, p);
      p0 = p1;
      p1 = p;
    }
  }
}

// Four lanes of doubles (GCC/Clang vector extension: one AVX2 register, two SSE2 ones).
typedef double V4 __attribute__((vector_size(32)));

// The inner loop is written for the vectoriser; on x86-64 GCC also builds an AVX2 version chosen
// at run time. AVX2 without FMA: products and sums round as in the baseline build, so both give
// the same bits.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && \
    !defined(__SANITIZE_ADDRESS__)
#define MICROBRDF_SIMD_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define MICROBRDF_SIMD_CLONES
#endif

// acc[sh_odd_index(l, m)] += weight * Y_lm over four directions (x, y, z lanes), l + m odd.
MICROBRDF_SIMD_CLONES
void odd_sum4(int lmax, const double* xs, const double* ys, const double* zs, const double* ws,
              V4* acc) {
  const Tables& t = tables();
  V4 wx, wy, wz, wt;
  for (int k = 0; k < 4; ++k) {
    wx[k] = xs[k];
    wy[k] = ys[k];
    wz[k] = zs[k];
    wt[k] = ws[k];
  }
  const V4 rho2 = wx * wx + wy * wy;
  V4 x, s, cphi, sphi;
  for (int k = 0; k < 4; ++k) {  // (sqrt and the pole cases lane by lane)
    const double rho = std::sqrt(rho2[k]), r = std::sqrt(rho2[k] + wz[k] * wz[k]);
    x[k] = r > 0 ? wz[k] / r : 1.0;
    s[k] = r > 0 ? rho / r : 0.0;
    cphi[k] = rho > 0 ? wx[k] / rho : 1.0;
    sphi[k] = rho > 0 ? wy[k] / rho : 0.0;
  }
  constexpr double kSqrt2 = 1.41421356237309504880;
  const double y00 = 1 / std::sqrt(4 * kPi);
  V4 pmm = {y00, y00, y00, y00};
  V4 cm = {1, 1, 1, 1}, sm = {0, 0, 0, 0};
  for (int m = 0; m <= lmax; ++m) {
    if (m > 0) {
      pmm = pmm * (t.diag[m] * s);
      const V4 c = cm * cphi - sm * sphi;
      sm = sm * cphi + cm * sphi;
      cm = c;
    }
    const V4 fc = m == 0 ? wt : wt * (kSqrt2 * cm), fs = wt * (kSqrt2 * sm);
    // l = m (odd only when m is odd: l + m = 2m is even), then l = m + 1, ...
    if (m + 1 > lmax) break;
    V4 p0 = pmm, p1 = t.sub[m] * x * pmm;
    // l = m + 1: l + m odd.
    acc[sh_odd_index(m + 1, m)] += p1 * fc;
    if (m > 0) acc[sh_odd_index(m + 1, -m)] += p1 * fs;
    for (int l = m + 2; l <= lmax; ++l) {
      const int i = l * (l + 1) / 2 + m;
      const V4 p = t.a[i] * (x * p1 - t.b[i] * p0);
      if ((l + m) & 1) {
        acc[sh_odd_index(l, m)] += p * fc;
        if (m > 0) acc[sh_odd_index(l, -m)] += p * fs;
      }
      p0 = p1;
      p1 = p;
    }
  }
}

}  // namespace

void sh_eval(int lmax, const Vec3& w, double* out) {
  check_lmax(lmax, 0);
  eval_core<false>(lmax, w, out);
}

ShOddBasis::ShOddBasis(int lmax) : lmax_(lmax) {
  check_lmax(lmax, 1);
  for (int l = 0; l <= lmax; ++l)
    for (int m = -l; m <= l; ++m)
      if ((l + m) & 1) {
        l_.push_back(l);
        m_.push_back(m);
      }
  // Hemisphere integrals: the phi integral kills m != 0; for m = 0 it is 2 pi int_0^1 Pbar_l(x)
  // dx, a polynomial of degree <= lmax, integrated exactly by Gauss-Legendre with lmax/2 + 2
  // nodes on [0, 1].
  hemi_.assign(l_.size(), 0.0);
  std::vector<double> gx, gw, y(l_.size());
  gauss_legendre(lmax / 2 + 2, gx, gw);
  for (std::size_t q = 0; q < gx.size(); ++q) {
    const double z = 0.5 * (gx[q] + 1);
    eval(Vec3(std::sqrt(1 - z * z), 0, z), y.data());
    for (std::size_t j = 0; j < l_.size(); ++j)
      if (m_[j] == 0) hemi_[j] += 2 * kPi * 0.5 * gw[q] * y[j];
  }
}

void ShOddBasis::eval(const Vec3& w, double* out) const { eval_core<true>(lmax_, w, out); }

void ShOddBasis::eval_sum(std::size_t n, const Vec3* w, const double* weight, double* out) const {
  const int J = size();
  // Accumulators per thread, 32-byte aligned (alignof(V4) is 16 where AVX is off, 32 in the AVX2
  // clone).
  struct Buffer {
    V4* p = nullptr;
    std::size_t n = 0;
    ~Buffer() { ::operator delete(p, std::align_val_t(32)); }
  };
  thread_local Buffer buf;
  if (buf.n < static_cast<std::size_t>(J)) {
    ::operator delete(buf.p, std::align_val_t(32));
    buf.p = nullptr;
    buf.p = static_cast<V4*>(::operator new(J * sizeof(V4), std::align_val_t(32)));
    buf.n = static_cast<std::size_t>(J);
  }
  V4* acc = buf.p;
  for (int j = 0; j < J; ++j) acc[j] = V4{0, 0, 0, 0};
  for (std::size_t k0 = 0; k0 < n; k0 += 4) {
    double xs[4] = {0, 0, 0, 0}, ys[4] = {0, 0, 0, 0}, zs[4] = {1, 1, 1, 1}, ws[4] = {0, 0, 0, 0};
    for (std::size_t k = k0; k < std::min(n, k0 + 4); ++k) {
      xs[k - k0] = w[k].x();
      ys[k - k0] = w[k].y();
      zs[k - k0] = w[k].z();
      ws[k - k0] = weight[k];
    }
    odd_sum4(lmax_, xs, ys, zs, ws, acc);
  }
  for (int j = 0; j < J; ++j) out[j] = (acc[j][0] + acc[j][1]) + (acc[j][2] + acc[j][3]);
}

}  // namespace microbrdf
