// Student-t slope statistics: incomplete beta, tails, quantiles, Smith Lambda, visible slopes
// (models/student_t_math.hpp).
#include "models/student_t_math.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "microbrdf/quadrature.hpp"
#include "models/beckmann_math.hpp"

namespace microbrdf::student_t {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kLogSqrtPi = 0.57236494292470008707;  // ln sqrt(pi)
// Slopes are clamped here: squares stay finite, and a normal built from two of them too.
constexpr double kMaxSlope = 1e150;
constexpr double kTol = 1e-12;  // in s = asinh(slope): |dx| < 1e-12 (1 + |x|)

/// 1/(1 + d1/(1 + d2/(1 + ...))), the continued fraction of I_x(p, q) (DLMF 8.17.22), by the
/// modified Lentz method. Converges quickly for x < (p + 1)/(p + q + 2); O(sqrt(max(p, q)))
/// terms at worst.
double beta_fraction(double p, double q, double x) {
  constexpr double kTiny = 1e-300;
  double f = 1, c = 1, d = 0;
  for (int m = 0; m < 100000; ++m) {
    // d_(2m+1) then d_(2m+2)
    for (int half = 0; half < 2; ++half) {
      const double k = half == 0 ? -(p + m) * (p + q + m) * x / ((p + 2 * m) * (p + 2 * m + 1))
                                 : (m + 1) * (q - m - 1) * x / ((p + 2 * m + 1) * (p + 2 * m + 2));
      d = 1 + k * d;
      if (std::abs(d) < kTiny) d = kTiny;
      c = 1 + k / c;
      if (std::abs(c) < kTiny) c = kTiny;
      d = 1 / d;
      const double delta = c * d;
      f *= delta;
      if (std::abs(delta - 1) < 3e-16) return 1 / f;  // within an ulp or two of 1
    }
  }
  return 1 / f;
}

/// Root of an increasing h(s) (returns {h, dh/ds, d2h/ds2}) in [lo, hi], starting at s: Halley
/// steps (Newton's where Halley's correction is large) while they stay inside the shrinking
/// bracket and shrink fast enough, bisection otherwise.
template <class H>
double solve_increasing(const H& h, double lo, double hi, double s) {
  if (!(s > lo && s < hi)) s = 0.5 * (lo + hi);
  double dx_old = hi - lo, dx = dx_old;
  for (int it = 0; it < 300; ++it) {
    const auto [f, df, d2f] = h(s);
    if (f == 0) return s;
    if (f < 0)
      lo = s;
    else
      hi = s;
    double step = f / df;
    const double c = 0.5 * step * d2f / df;  // Halley: step / (1 - f f''/(2 f'^2))
    const bool halley = std::abs(c) < 0.5;
    if (halley) step /= 1 - c;
    const double next = s - step;
    // Cubic convergence: after a Halley step below 1e-5 the error is ~1e-15 (times the smooth
    // function's third-derivative ratio), so that step ends the iteration.
    if (halley && std::abs(step) < 1e-5 && next > lo && next < hi) return next;
    if (!(next > lo && next < hi) || !(std::abs(2 * f) <= std::abs(dx_old * df))) {
      dx_old = dx;
      dx = 0.5 * (hi - lo);
      s = lo + dx;
    } else {
      dx_old = dx;
      dx = step;
      s = next;
    }
    if (std::abs(dx) < kTol || hi - lo < kTol) break;
  }
  return s;
}

}  // namespace

double log_beta_half(double b) {
  if (b < 30) return kLogSqrtPi + std::lgamma(b) - std::lgamma(b + 0.5);
  // ln Gamma(b + 1/2) - ln Gamma(b) = ln(b)/2 - 1/(8b) + 1/(192b^3) - 1/(640b^5) + 17/(14336b^7)
  // - ...; the next term is below 1e-16 for b >= 30.
  const double r = 1 / b, r2 = r * r;
  const double lr =
      0.5 * std::log(b) - r * (0.125 - r2 * (1.0 / 192 - r2 * (1.0 / 640 - r2 * (17.0 / 14336))));
  return kLogSqrtPi - lr;
}

double ibeta_half(double b, double x, double y, double log_beta) {
  if (x <= 0) return 0;
  if (y <= 0) return 1;
  const double lx = x > 0.5 ? std::log1p(-y) : std::log(x);
  const double ly = y > 0.5 ? std::log1p(-x) : std::log(y);
  const double front = b * lx + 0.5 * ly - log_beta;  // ln(x^b y^(1/2) / B(b, 1/2))
  if (x < (b + 1) / (b + 2.5)) return std::exp(front - std::log(b)) * beta_fraction(b, 0.5, x);
  return 1 - std::exp(front + std::log(2.0)) * beta_fraction(0.5, b, y);
}

// ---------------------------------------------------------------------------------------------
Shape::Shape(double b) : b_(b), log_beta_(log_beta_half(b)), inv_beta_(std::exp(-log_beta_)) {}

double Shape::density(double w) const {
  return std::exp(-(b_ + 0.5) * std::log1p(w * w) - log_beta_);
}

double Shape::tail(double w) const {
  const double aw = std::min(std::abs(w), kMaxSlope), w2 = aw * aw;
  // W <= -|w| <=> cos^2 of atan(W) <= 1/(1 + w^2): half of I_(1/(1+w^2))(b, 1/2).
  return 0.5 * ibeta_half(b_, 1 / (1 + w2), w2 / (1 + w2), log_beta_);
}

double Shape::approximate_quantile(double u) const {
  const double nu = 2 * b_, z = std::sqrt(2.0) * beckmann::gauss_quantile(u), z2 = z * z;
  const double t = z * (1 + (z2 + 1) / (4 * nu) + ((5 * z2 + 16) * z2 + 3) / (96 * nu * nu));
  return t / std::sqrt(nu);
}

double Shape::quantile(double u) const {
  const double q = std::max(u <= 0.5 ? u : 1 - u, 1e-300);
  if (q >= 0.5) return 0;
  // Bracket of the root w <= 0 of tail(w) = q: the tail is below |w|^-2b / (2b B) (drop the 1 in
  // 1 + t^2), and above the tangent 1/2 + w/B at 0 (the cdf is convex for w < 0).
  const double w_lo =
      -std::min(kMaxSlope, std::exp(-(std::log(2 * b_ * q) + log_beta_) / (2 * b_)));
  const double w_hi = std::min(0.0, std::max(w_lo, (q - 0.5) / inv_beta_));
  const double lq = std::log(q);
  // h = ln tail(w) - ln q, w = sinh s: h' = f cosh s / tail = r, and since
  // f'(w) = -(2b + 1) w f/(1 + w^2) and cosh^2 s = 1 + w^2, h'' = -2b w f/tail - r^2.
  auto h = [&](double s) {
    const double w = std::sinh(s), t = tail(w), ft = density(w) / t, r = ft * std::cosh(s);
    return std::array{std::log(t) - lq, r, -2 * b_ * w * ft - r * r};
  };
  const double lo = std::asinh(w_lo), hi = std::asinh(w_hi);
  // Start: the Cornish-Fisher value for b >= 1, else the tail bound (the asymptote for small q)
  // or the tangent.
  const double start = b_ >= 1 ? std::asinh(approximate_quantile(q)) : (q < 0.05 ? lo : hi);
  const double w = std::sinh(solve_increasing(h, lo, hi, start));
  return u <= 0.5 ? w : -w;
}

// ---------------------------------------------------------------------------------------------
Slopes::Slopes(double gamma)
    : x_(gamma - 1),
      y_(gamma - 0.5),
      a_(gamma - 1),
      sqrt_a_(std::sqrt(gamma - 1)),
      inv_sqrt_a_(1 / std::sqrt(gamma - 1)),
      finite_(gamma > 1.5) {
  g0_ = finite_ ? sqrt_a_ * std::exp(-x_.log_beta()) / (2 * a_ - 1) : kInf;
  gauss_legendre(10, gl_x_, gl_w_);
}

double Slopes::G(double x) const { return g0_ * std::exp((0.5 - a_) * std::log1p(x * x / a_)); }

double Slopes::G_inverse(double y) const {
  if (!(y < g0_)) return 0;
  const double t = std::log(g0_ / y) / (a_ - 0.5);  // ln(1 + x^2/a)
  return std::min(kMaxSlope, std::sqrt(a_ * std::expm1(t)));
}

double Slopes::lambda(double mu) const {
  if (!(mu < kInf)) return 0;
  if (!finite_) return kInf;
  return std::max(0.0, G(mu) / mu - x_.tail(mu * inv_sqrt_a_));
}

double Slopes::C(double mu, double x) const { return mu * x_.cdf(x * inv_sqrt_a_) + G(x); }

double Slopes::C_above(double mu, double tm, double x) const {
  if (mu - x < 0.25) {
    // Close to mu the closed form below cancels to ~1e-16 absolute against a value
    // ~P2 (mu - x)^2/2; integrate (mu - t) P2(t) over [x, mu] instead (P2's poles at +-i sqrt(a),
    // a > 1/2, are > 0.7 away: 10 Gauss points are exact to rounding on this short interval).
    const double h = 0.5 * (mu - x), c = 0.5 * (mu + x);
    double sum = 0;
    for (std::size_t i = 0; i < gl_x_.size(); ++i) {
      const double t = c + h * gl_x_[i];
      sum += gl_w_[i] * (mu - t) * marginal(t);
    }
    return sum * h;
  }
  const double tx = x_.tail(x * inv_sqrt_a_);
  const double df = x >= 0 ? tx - tm : (1 - tm) - tx;  // F(mu) - F(x) from the smaller tails
  return std::max(0.0, mu * df + (G(mu) - G(x)));
}

std::array<double, 2> Slopes::weight(double mu, double s) const {
  // q = (mu - x) P2(x) cosh s, x = sinh s; with P2'/P2 = -(2a + 1) x/(a + x^2),
  // dq/ds = P2 (cosh^2 s (-1 - (mu - x)(2a + 1) x/(a + x^2)) + (mu - x) x).
  const double x = std::sinh(s), c = std::cosh(s), p = marginal(x), d = mu - x;
  return {d * p * c, p * (c * c * (-1 - d * (2 * a_ + 1) * x / (a_ + x * x)) + d * x)};
}

double Slopes::visible_slope(double mu, double u) const {
  // Far from grazing the weight (mu - x) is constant to rounding: the marginal itself.
  if (!finite_ || !(mu * 1e-16 < g0_)) return sqrt_a_ * x_.quantile(u);
  const double t_mu = x_.tail(mu * inv_sqrt_a_), c_mu = mu * (1 - t_mu) + G(mu);  // mu (1 + Lambda)
  const double hi = std::asinh(mu);
  // Lower bound of any root below the median: for x <= -mu, C(x) <= G(x) (1 + mu/|x|) <= 2 G(x)
  // (since F(x) <= G(x)/|x|), so C <= y where G = y/2.
  auto lower = [&](double y) { return std::asinh(-std::max(mu, G_inverse(0.5 * y))); };
  // Away from grazing (mu >= 2) and for a >= 1, a close start: the marginal's approximate
  // quantile x0 and one Newton step on C towards u C(mu), using F(x0) ~ u:
  // x1 = x0 - (G(x0) - u mu Lambda) / ((mu - x0) P2(x0)).
  double x1 = std::numeric_limits<double>::quiet_NaN();
  if (a_ >= 1 && mu >= 2) {
    const double x0 = sqrt_a_ * x_.approximate_quantile(u), lambda = c_mu / mu - 1;
    x1 = x0 - (G(x0) - u * mu * lambda) / ((mu - x0) * marginal(x0));
  }
  const bool close = x1 < mu;  // false for NaN
  double s;
  if (u <= 0.5) {
    const double target = std::max(u * c_mu, 1e-300), lt = std::log(target);
    auto h = [&](double s) {
      const auto [q, dq] = weight(mu, s);
      const double c = C(mu, std::sinh(s)), r = q / c;
      return std::array{std::log(c) - lt, r, dq / c - r * r};
    };
    // C(x) >= G(x): the root lies above -G^-1(target), the lower tail's asymptote.
    s = solve_increasing(h, lower(target), hi, std::asinh(close ? x1 : -G_inverse(target)));
  } else {
    const double target = (1 - u) * c_mu, rt = std::sqrt(target);
    auto h = [&](double s) {
      const auto [q, dq] = weight(mu, s);
      const double d = C_above(mu, t_mu, std::sinh(s)), r = std::sqrt(d);
      return std::array{rt - r, q / (2 * r), dq / (2 * r) + q * q / (4 * d * r)};
    };
    // Near mu, C(mu) - C(x) ~ P2(mu) (mu - x)^2 / 2.
    const double start = close ? x1 : mu - std::sqrt(2 * target / marginal(mu));
    s = solve_increasing(h, lower(0.5 * c_mu), hi, std::asinh(start));
  }
  return std::min(mu, std::sinh(s));
}

double Slopes::perpendicular_slope(double x, double u) const {
  const double w = y_.quantile(u);
  return std::clamp(std::sqrt(a_ + x * x) * w, -kMaxSlope, kMaxSlope);
}

}  // namespace microbrdf::student_t
