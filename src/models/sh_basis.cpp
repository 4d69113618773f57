// Real spherical harmonics by the normalised associated-Legendre recurrence (docs/theory.md §6.1)
// and the odd-completion basis (docs/theory.md §6.2). See include/microbrdf/sh_basis.hpp.
#include "microbrdf/sh_basis.hpp"

#include <algorithm>
#include <cmath>
#include <new>
#include <string>
#include <vector>

#include "core/simd_clones.hpp"
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
typedef double V4 __attribute__((vector_size(4 * sizeof(double))));
// Directions per call: two groups of four, so two independent recurrences are in flight (the l
// recurrence is a chain of dependent products; one alone leaves the units idle).
constexpr int kGroups = 2, kLanes = 4 * kGroups;

// acc[kGroups * sh_odd_index(l, m) + g] += weight * Y_lm over kLanes directions (x, y, z, weight
// lanes; group g holds lanes 4g..4g+3), l + m odd.
MICROBRDF_SIMD_CLONES
void odd_sum8(int lmax, const double* xs, const double* ys, const double* zs, const double* ws,
              V4* acc) {
  const Tables& t = tables();
  V4 x[kGroups], s[kGroups], cphi[kGroups], sphi[kGroups], wt[kGroups];
  for (int k = 0; k < kLanes; ++k) {  // (sqrt and the pole cases lane by lane)
    const int g = k / 4, e = k % 4;
    const double rho = std::sqrt(xs[k] * xs[k] + ys[k] * ys[k]);
    const double r = std::sqrt(rho * rho + zs[k] * zs[k]);
    x[g][e] = r > 0 ? zs[k] / r : 1.0;
    s[g][e] = r > 0 ? rho / r : 0.0;
    cphi[g][e] = rho > 0 ? xs[k] / rho : 1.0;
    sphi[g][e] = rho > 0 ? ys[k] / rho : 0.0;
    wt[g][e] = ws[k];
  }
  constexpr double kSqrt2 = 1.41421356237309504880;
  const double y00 = 1 / std::sqrt(4 * kPi);
  V4 pmm[kGroups], cm[kGroups], sm[kGroups];
  for (int g = 0; g < kGroups; ++g) {
    pmm[g] = V4{y00, y00, y00, y00};
    cm[g] = V4{1, 1, 1, 1};
    sm[g] = V4{0, 0, 0, 0};
  }
  for (int m = 0; m <= lmax; ++m) {
    V4 fc[kGroups], fs[kGroups], p0[kGroups], p1[kGroups];
    for (int g = 0; g < kGroups; ++g) {
      if (m > 0) {
        pmm[g] = pmm[g] * (t.diag[m] * s[g]);
        const V4 c = cm[g] * cphi[g] - sm[g] * sphi[g];
        sm[g] = sm[g] * cphi[g] + cm[g] * sphi[g];
        cm[g] = c;
      }
      fc[g] = m == 0 ? wt[g] : wt[g] * (kSqrt2 * cm[g]);
      fs[g] = wt[g] * (kSqrt2 * sm[g]);
    }
    // l = m has l + m even (dropped); l = m + 1 is kept.
    if (m + 1 > lmax) break;
    V4* a = acc + kGroups * sh_odd_index(m + 1, m);
    V4* b = acc + kGroups * sh_odd_index(m + 1, -m);
    for (int g = 0; g < kGroups; ++g) {
      p0[g] = pmm[g];
      p1[g] = t.sub[m] * x[g] * pmm[g];
      a[g] += p1[g] * fc[g];
      if (m > 0) b[g] += p1[g] * fs[g];
    }
    for (int l = m + 2; l <= lmax; ++l) {
      const int i = l * (l + 1) / 2 + m;
      const double ai = t.a[i], bi = t.b[i];
      const bool keep = (l + m) & 1;
      V4* al = acc + kGroups * sh_odd_index(l, m);
      V4* bl = acc + kGroups * sh_odd_index(l, -m);
      for (int g = 0; g < kGroups; ++g) {
        const V4 p = ai * (x[g] * p1[g] - bi * p0[g]);
        if (keep) {
          al[g] += p * fc[g];
          if (m > 0) bl[g] += p * fs[g];
        }
        p0[g] = p1[g];
        p1[g] = p;
      }
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
  // Accumulators per thread, kGroups per function, 32-byte aligned (alignof(V4) is only 16
  // where AVX is off; the AVX2 clone expects 32).
  struct Buffer {
    V4* p = nullptr;
    std::size_t n = 0;
    ~Buffer() { ::operator delete(p, std::align_val_t(32)); }
  };
  thread_local Buffer buf;
  const std::size_t need = static_cast<std::size_t>(kGroups) * J;
  if (buf.n < need) {
    ::operator delete(buf.p, std::align_val_t(32));
    buf.p = nullptr;
    buf.p = static_cast<V4*>(::operator new(need * sizeof(V4), std::align_val_t(32)));
    buf.n = need;
  }
  V4* acc = buf.p;
  for (std::size_t j = 0; j < need; ++j) acc[j] = V4{0, 0, 0, 0};
  for (std::size_t k0 = 0; k0 < n; k0 += kLanes) {
    double xs[kLanes] = {}, ys[kLanes] = {}, zs[kLanes] = {}, ws[kLanes] = {};
    for (std::size_t k = k0; k < std::min(n, k0 + kLanes); ++k) {
      xs[k - k0] = w[k].x();
      ys[k - k0] = w[k].y();
      zs[k - k0] = w[k].z();
      ws[k - k0] = weight[k];
    }
    odd_sum8(lmax_, xs, ys, zs, ws, acc);
  }
  for (int j = 0; j < J; ++j) {
    const V4 a = acc[kGroups * j], b = acc[kGroups * j + 1];
    out[j] = ((a[0] + a[1]) + (a[2] + a[3])) + ((b[0] + b[1]) + (b[2] + b[3]));
  }
}

}  // namespace microbrdf
