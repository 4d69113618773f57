#pragma once
// One-dimensional special functions of the Student-t slope distribution (models/student_t.cpp),
// exposed for the tests.
//
// With a = gamma - 1 and the slopes stretched to alpha = 1, the 2-D slope density is
// P22(x, y) = (1 + (x^2 + y^2)/a)^-(a+1) / pi. Both of its 1-D pieces are of one family,
//   f_b(w) = (1 + w^2)^-(b + 1/2) / B(b, 1/2),   b > 0
// (a Student-t with 2b degrees of freedom, scaled by 1/sqrt(2b)):
//   - the marginal slope along any axis, P2(x) = f_a(x / sqrt(a)) / sqrt(a);
//   - the slope across it given x: y = sqrt(a + x^2) w with w ~ f_(a + 1/2).
// Everything below is built on the regularised incomplete beta function I_x(b, 1/2) (its
// continued fraction), which is the Gauss hypergeometric 2F1 of the paper's formulas:
// I_x(b, 1/2) = x^b (1 - x)^(1/2) 2F1(b + 1/2, 1; b + 1; x) / (b B(b, 1/2)) (DLMF 8.17.8).

#include <array>
#include <vector>

namespace microbrdf::student_t {

/// ln B(b, 1/2) = ln(sqrt(pi) Gamma(b) / Gamma(b + 1/2)), b > 0: std::lgamma below b = 30, an
/// asymptotic series above (absolute error < 1e-16 there; lgamma's difference would lose ~1e-11
/// at b = 1e4).
double log_beta_half(double b);

/// The regularised incomplete beta I_x(b, 1/2) for 0 <= x <= 1, given x and y = 1 - x separately
/// (so that x near 1 does not cancel): the continued fraction DLMF 8.17.22 by the modified Lentz
/// method on I_x(b, 1/2) or on 1 - I_y(1/2, b), whichever converges; relative error ~1e-15.
double ibeta_half(double b, double x, double y, double log_beta);

/// The family f_b above: its lower tail, density and quantile.
class Shape {
 public:
  explicit Shape(double b);
  double b() const { return b_; }
  double log_beta() const { return log_beta_; }
  /// f_b(w).
  double density(double w) const;
  /// P(W <= -|w|), relative error ~1e-15 however far out (|w| up to 1e150).
  double tail(double w) const;
  /// P(W <= w).
  double cdf(double w) const { return w <= 0 ? tail(w) : 1 - tail(w); }
  /// The w with cdf(w) = u, u in [0, 1) (u = 0 and results beyond 1e150 are clamped to
  /// -+1e150): safeguarded Halley iteration on ln tail in s = asinh(w); |dw| ~1e-12 (1 + |w|).
  double quantile(double u) const;
  /// The Cornish-Fisher expansion of that quantile for b >= 1 (Student's t with nu = 2b degrees
  /// of freedom, t = z + (z^3 + z)/(4 nu) + (5z^5 + 16z^3 + 3z)/(96 nu^2), w = t/sqrt(nu), z the
  /// normal quantile): a start for the iterations, good to ~nu^-3.
  double approximate_quantile(double u) const;

 private:
  double b_, log_beta_, inv_beta_;
};

/// The slope statistics of one gamma in the stretched configuration (alpha = 1).
class Slopes {
 public:
  explicit Slopes(double gamma);
  double gamma() const { return a_ + 1; }
  /// False for gamma <= 1.5: the mean |slope| is infinite, so sigma+(v) is infinite for every v
  /// off the normal (Lambda = +inf, G1 = 0).
  bool finite_lambda() const { return finite_; }
  /// P2(x), the marginal slope density.
  double marginal(double x) const { return x_.density(x * inv_sqrt_a_) * inv_sqrt_a_; }
  /// Smith Lambda for mu = 1/(alpha_v tan theta_v) > 0 (mu = inf: 0):
  /// Lambda = (1/mu) integral_mu^inf (x - mu) P2(x) dx = G(mu)/mu - S(mu), S the upper tail of
  /// P2 and G(mu) = integral_mu^inf x P2(x) dx = sqrt(a) (1 + mu^2/a)^(1/2 - a) / ((2a-1)
  /// B(a,1/2)).
  double lambda(double mu) const;
  /// The slope along the view azimuth of a visible normal: x with density proportional to
  /// <mu - x>+ P2(x), from u in [0, 1) by inverting its CDF C(x) = mu F(x) + G(x) (x <= mu;
  /// C(mu) = mu (1 + Lambda)) with safeguarded Halley iteration in s = asinh(x): on ln C below
  /// the median, on sqrt(C(mu) - C(x)) above it (both nearly linear in s at their ends);
  /// |dx| ~1e-11 (1 + |x|). mu = inf (or gamma <= 1.5): the marginal P2 itself.
  double visible_slope(double mu, double u) const;
  /// The slope across the view given the slope x along it: sqrt(a + x^2) times the quantile of
  /// f_(a + 1/2) at u.
  double perpendicular_slope(double x, double u) const;

 private:
  double C(double mu, double x) const;                        // mu F(x) + G(x)
  double C_above(double mu, double tail_mu, double x) const;  // C(mu) - C(x), no cancelling
  std::array<double, 2> weight(double mu, double s) const;    // d/ds C(sinh s) and its derivative
  double G(double x) const;                                   // integral_-inf^x (-t) P2(t) dt
  double G_inverse(double y) const;                           // |x| with G(x) = y (0 if y >= G(0))
  std::vector<double> gl_x_, gl_w_;                           // 10-point Gauss-Legendre rule
  Shape x_, y_;                          // f_a (marginal) and f_(a + 1/2) (conditional)
  double a_, sqrt_a_, inv_sqrt_a_, g0_;  // g0_ = G(0)
  bool finite_;
};

}  // namespace microbrdf::student_t
