// The visible-slope quantile of the Beckmann distribution (beckmann_math.hpp).
//
// x has density proportional to <mu - x>+ exp(-x^2); its CDF (unnormalised) is
//   C(x) = mu sqrt(pi)/2 erfc(-x) + exp(-x^2)/2  (x <= mu),
// and the sample is the root of C(x) = u C(mu). C(x)/(mu sqrt(pi)) = Phi(x) + phi(x)/(2 mu)
// exactly (Phi the CDF of exp(-x^2)/sqrt(pi), phi its density), whose root for large mu is
//   x0 - 1/(2 mu) - x0/(4 mu^2) + (1 - 2 x0^2)/(12 mu^3) + O(mu^-4),
// x0 the Gaussian quantile of u C(mu)/(mu sqrt(pi)) (series() below). The iteration starts from
//  - mu >= 1: that series at x0 = the Gaussian quantile of u plus a correction interpolated
//    bilinearly in (1/mu, x0) from a table (which also absorbs C(mu)/(mu sqrt(pi)) - 1, so that
//    the start does not wait for C(mu));
//  - mu < 1: mu - v, v = sqrt(-ln u) (exact for mu = 0), plus a correction interpolated in
//    (mu, v) from a second table;
//  - elsewhere (tails beyond the tables): mu - v, raised for u > 1/2 and mu < 5 to mu - z0 (the
//    mass above x is >= exp(-mu^2) (mu - x)^2 / 2 for x >= -mu, so the root lies at or above
//    mu - z0, z0 = sqrt(2 (1-u) C(mu) exp(mu^2)); also the asymptotic root for u -> 1).
// The tables hold the exact roots at their nodes (computed once, on first use, by the same
// iteration run to 1e-7 Halley steps, i.e. ~1e-20); the interpolated start is within 1e-4 (1 + |x|)
// of the root for ~98% of (mu, u) (tests/test_beckmann_math.cpp), so one Halley step usually ends
// the iteration (1.01-1.04 steps on average for alpha 0.08-1 and uniform cos theta views).
// Below the median, Halley's method runs on ln C (nearly quadratic in the lower tail; written as
// -x^2 + ln(...) for x <= 0, so nothing underflows), above it on the ln of the mass above x
// (C(mu) - C(x) ~ (mu - x)^2 near the end), both monotone with a bracket [lo, mu]; a step leaving
// the bracket is replaced by bisection. A Halley step below 1e-4 (1 + |x|) (above the median:
// 1e-4 min(1 + |x|, mu - x), the scale of ln(mu - x)) ends the iteration: convergence is cubic,
// so ~1e-12 is left (the tests assert 1e-10 (1 + |x|) against a long-double bisection). A Newton
// step (taken where Halley's correction is large) ends it below 1e-8 (1 + |x|).
#include "models/beckmann_math.hpp"

#include <array>

namespace microbrdf::beckmann {
namespace {

// Table A: 1/mu in [0, 1], x0 in [-7, 7]; table B: mu in [0, 1], v in [0, 6.5]; 33 x 257 floats
// each (34 kB). The finer axis matters: 65 x 129 nodes start within 1e-4 for 91% of the test
// points, 33 x 257 for 98-99%.
constexpr int kNa = 32, kNx = 256, kNb = 32, kNv = 256;
constexpr double kX0 = -7, kX1 = 7, kV1 = 6.5;

struct SlopeView {
  double mu, e_mu, erfc_mu, c_mu, half_mu_sqrt_pi;
};

SlopeView slope_view(double mu) {
  SlopeView s;
  s.mu = mu;
  s.half_mu_sqrt_pi = 0.5 * mu * kSqrtPi;
  // Above mu = 8, exp(-mu^2) < 1.6e-28 and erfc(mu) < 2e-30: below the rounding of C(mu) and of
  // every mass the iteration compares (>= 2^-53 C(mu), u being a double below 1).
  s.e_mu = mu < 8 ? exp_minus_sq(mu) : 0.0;
  s.erfc_mu = mu < 8 ? s.e_mu * erfcx(mu) : 0.0;
  s.c_mu = s.half_mu_sqrt_pi * (2 - s.erfc_mu) + 0.5 * s.e_mu;  // erfc(-mu) = 2 - erfc(mu)
  return s;
}

double series(double x0, double eps) {
  return x0 - eps * (0.5 + eps * (0.25 * x0 - eps * (1 - 2 * x0 * x0) * (1.0 / 12)));
}

// The start without the tables.
double plain_start(const SlopeView& s, double u) {
  const double mu = s.mu;
  double x = mu - std::sqrt(-std::log(std::max(u, 1e-300)));
  if (u > 0.5 && mu < 5) {
    const double z0 = std::sqrt(2 * (1 - u) * s.c_mu / s.e_mu);
    if (!(x < mu) || x < mu - z0) x = mu - z0;
  }
  return x;
}

// Safeguarded Halley iteration from x (see the file comment); `halley_tol` ends it.
double refine(const SlopeView& s, double u, double x, double halley_tol) {
  const double mu = s.mu, hmsp = s.half_mu_sqrt_pi;
  const bool upper = u > 0.5;
  const double target = upper ? (1 - u) * s.c_mu : u * s.c_mu;  // mass above / below the root
  const double inv_target = 1 / target;
  double lo = -30, hi = mu;
  if (!(x > lo && x < hi)) x = 0.5 * (std::max(lo, -6.0) + hi);
  for (int it = 0; it < 200; ++it) {
    // g = ln(K / target), K = C (below the median) or C(mu) - C (above), with G1 = g' K and
    // G2 = g'' K^2 (free of divisions): Halley's step g g' / (g'^2 - g g''/2) is then
    // g K G1 / (G1^2 - g G2 / 2) and Newton's g K / G1.
    double g, k, G1, G2;
    const double d = mu - x;
    if (!upper && x <= 0) {
      // C = exp(-x^2) A, A = mu sqrt(pi)/2 erfcx(-x) + 1/2; C' = d exp(-x^2),
      // C'' = -(1 + 2 x d) exp(-x^2); K = A (the factor exp(-x^2) cancels in g' and g'')
      k = hmsp * erfcx(-x) + 0.5;
      g = std::log(k * inv_target) - x * x;
      G1 = d;
      G2 = -(1 + 2 * x * d) * k - d * d;
    } else {
      const double e = exp_minus_sq(x);
      const double erfc_x = x >= 0 ? e * erfcx(x) : 2 - e * erfcx(-x);
      const double p = d * e, c2 = -(1 + 2 * x * d) * e;  // C', C''
      if (!upper) {
        k = hmsp * (2 - erfc_x) + 0.5 * e;
        g = std::log(k * inv_target);
        G1 = p;
        G2 = c2 * k - p * p;
      } else {
        // C(mu) - C(x) from the differences of erfc and exp (no cancellation against
        // mu sqrt(pi), which C(mu) - C(x) computed directly would suffer for large mu)
        k = hmsp * (erfc_x - s.erfc_mu) - 0.5 * (e - s.e_mu);
        if (k > 0) {
          g = std::log(k * inv_target);
          G1 = -p;
          G2 = -c2 * k - p * p;
        } else {  // at or beyond the end: right of the root, a unit step (then bisection)
          g = -1;
          k = 1;
          G1 = -1;
          G2 = 0;
        }
      }
    }
    if (upper ? g < 0 : g > 0)  // x lies right of the root
      hi = x;
    else
      lo = x;
    const bool halley = std::abs(g * G2) < G1 * G1;  // Halley's correction factor within 2
    const double dx = halley ? g * k * G1 / (G1 * G1 - 0.5 * g * G2) : g * k / G1;
    const double xn = x - dx;
    // (near the end of the range, the upper function ~ 2 ln(mu - x): steps relative to mu - x)
    const double scale = upper ? std::min(1 + std::abs(x), d) : 1 + std::abs(x);
    if (std::abs(dx) <= (halley ? halley_tol : 1e-8) * scale) return std::clamp(xn, lo, hi);
    if (xn > lo && xn < hi) {
      x = xn;
    } else {
      x = 0.5 * (lo + hi);
      if (hi - lo <= 1e-14 * (1 + std::abs(x))) return x;
    }
  }
  return x;
}

struct Tables {
  // corrections to series() (a) and to mu - v (b) at the nodes, float: they are starts only
  std::array<float, (kNa + 1) * (kNx + 1)> a{};
  std::array<float, (kNb + 1) * (kNv + 1)> b{};
};

Tables build_tables() {
  Tables t;
  for (int i = 1; i <= kNa; ++i) {  // i = 0: mu = inf, correction 0
    const double eps = double(i) / kNa, mu = 1 / eps;
    const SlopeView s = slope_view(mu);
    for (int j = 0; j <= kNx; ++j) {
      const double x0 = kX0 + (kX1 - kX0) * j / kNx;
      const double u = x0 <= 0 ? 0.5 * erfc(-x0) : 1 - 0.5 * erfc(x0);
      const double x = refine(s, u, plain_start(s, u), 1e-7);
      t.a[i * (kNx + 1) + j] = float(x - series(x0, eps));
    }
  }
  for (int i = 0; i <= kNb; ++i) {
    const double mu = double(i) / kNb;
    const SlopeView s = slope_view(mu);
    for (int j = 1; j <= kNv; ++j) {  // j = 0: u = 1, the root is mu: correction 0
      const double v = kV1 * j / kNv, u = std::exp(-v * v);
      const double x = refine(s, u, plain_start(s, u), 1e-7);
      t.b[i * (kNv + 1) + j] = float(x - (mu - v));
    }
  }
  return t;
}

const Tables& tables() {
  static const Tables t = build_tables();
  return t;
}

// Bilinear interpolation at (fi, fj) in node units, 0 <= fi <= ni, 0 <= fj <= nj.
double bilinear(const float* t, int ni, int nj, double fi, double fj) {
  const int i = std::min(int(fi), ni - 1), j = std::min(int(fj), nj - 1);
  const double a = fi - i, b = fj - j;
  const float* r0 = t + i * (nj + 1) + j;
  const float* r1 = r0 + (nj + 1);
  return (1 - a) * ((1 - b) * r0[0] + b * r0[1]) + a * ((1 - b) * r1[0] + b * r1[1]);
}

double start(const SlopeView& s, double u) {
  const double mu = s.mu;
  if (mu >= 1) {
    const double eps = 1 / mu;
    const double x0 = erfinv_u(u);
    if (x0 >= kX0 && x0 <= kX1)
      return series(x0, eps) +
             bilinear(tables().a.data(), kNa, kNx, eps * kNa, (x0 - kX0) * (kNx / (kX1 - kX0)));
  } else if (mu >= 0 && u > 0) {
    const double v = std::sqrt(-std::log(u));
    if (v <= kV1) return mu - v + bilinear(tables().b.data(), kNb, kNv, mu * kNb, v * (kNv / kV1));
  }
  return plain_start(s, u);
}

}  // namespace

double visible_slope_start(double mu, double u) { return start(slope_view(mu), u); }

double visible_slope(double mu, double u) {
  if (!(mu < 1e8)) return gauss_quantile(u);
  const SlopeView s = slope_view(mu);
  return refine(s, u, start(s, u), 1e-4);
}

}  // namespace microbrdf::beckmann
