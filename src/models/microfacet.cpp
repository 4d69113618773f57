// Beckmann, GGX and ellipsoid microfacet distributions (include/microbrdf/microfacet.hpp).
#include "microbrdf/microfacet.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "microbrdf/error.hpp"

namespace microbrdf {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kSqrtPi = 1.77245385090551602730;

void check_alpha(double ax, double ay) {
  if (!(ax > 0 && ax <= 10 && ay > 0 && ay <= 10) || !std::isfinite(ax) || !std::isfinite(ay))
    throw InputError("roughness alpha must lie in (0, 10]");
}

std::string fmt_params(const char* name, double ax, double ay, const char* extra) {
  char b[160];
  std::snprintf(b, sizeof b, "%s alpha=(%.6g, %.6g)%s", name, ax, ay, extra);
  return b;
}

// Heitz 2018 step: a direction uniformly distributed in projected area, seen along the unit
// view `v` (v.z may be negative down to -1 exclusive), on the upper unit hemisphere.
Vec3 hemisphere_visible(const Vec3& v, double u1, double u2) {
  const double lensq = v.x() * v.x() + v.y() * v.y();
  const Vec3 t1 = lensq > 0 ? Vec3(-v.y(), v.x(), 0) / std::sqrt(lensq) : Vec3(1, 0, 0);
  const Vec3 t2 = v.cross(t1);
  const double r = std::sqrt(u1), phi = 2 * kPi * u2;
  const double p1 = r * std::cos(phi);
  double p2 = r * std::sin(phi);
  const double s = 0.5 * (1 + v.z());
  p2 = (1 - s) * std::sqrt(std::max(0.0, 1 - p1 * p1)) + s * p2;
  return p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0, 1 - p1 * p1 - p2 * p2)) * v;
}

// Approximate inverse error function (Winitzki), refined by Newton in the caller.
double erfinv_guess(double t) {
  t = std::clamp(t, -1 + 1e-16, 1 - 1e-16);
  const double a = 0.147;
  const double l = std::log(1 - t * t);
  const double b = 2 / (kPi * a) + 0.5 * l;
  return std::copysign(std::sqrt(std::sqrt(b * b - l / a) - b), t);
}

// Draws x with density proportional to <mu - x>+ exp(-x^2) (mu = cot theta of the stretched
// view; mu = +inf means exp(-x^2)) by inverting the CDF
//   C(x) = mu sqrt(pi)/2 erfc(-x) + exp(-x^2)/2  (x <= mu),  u C(mu) = C(x).
// Safeguarded Newton, started from a close guess so that 2-4 steps suffice:
//  - flat (mu = inf): Winitzki's erfinv, Newton on the CDF (on its complement above 1/2);
//  - mu > 1: the density ~ mu exp(-x^2 - x/mu) = Gaussian of mean -1/(2 mu): erfinv - 1/(2 mu);
//  - mu <= 1: mu - sqrt(-ln u), exact for mu = 0 (the density is then -2x exp(-x^2) on x < 0);
//  - u > 1/2 and mu < 5: the mass above x is >= exp(-mu^2) (mu - x)^2 / 2 for x >= -mu, so the
//    root lies at or above mu - z0, z0 = sqrt(2 (1-u) C(mu) exp(mu^2)); the guess is raised to
//    that bound (it is also the asymptotic root for u -> 1).
// Below the median Newton runs on ln C (nearly quadratic in the lower tail), above it on the ln
// of the mass above x (C(mu) - C(x) ~ (mu - x)^2 near the end), both monotone with a bracket
// [lo, mu]; a step leaving the bracket is replaced by bisection. The iteration stops when a
// Newton step is below 1e-8 (1 + |x|): convergence is quadratic, so the remaining error is
// ~1e-16, i.e. the root is as exact as the double-precision CDF allows (tested against a
// bisection to 1e-15).
double sample_visible_slope(double mu, double u) {
  if (!(mu < 1e8)) {
    double x = erfinv_guess(2 * u - 1);
    for (int it = 0; it < 50; ++it) {
      const double f = u < 0.5 ? 0.5 * std::erfc(-x) - u : (1 - u) - 0.5 * std::erfc(x);
      const double dx = f * kSqrtPi * std::exp(x * x);
      x -= dx;
      if (!(std::abs(dx) > 1e-8 * (1 + std::abs(x)))) break;
    }
    return x;
  }
  const double e_mu = std::exp(-mu * mu);
  const double c_mu = mu * 0.5 * kSqrtPi * std::erfc(-mu) + 0.5 * e_mu;
  const bool upper = u > 0.5;
  const double tail = (1 - u) * c_mu;  // mass above the root
  double x =
      mu > 1 ? erfinv_guess(2 * u - 1) - 0.5 / mu : mu - std::sqrt(-std::log(std::max(u, 1e-300)));
  if (upper && mu < 5) {
    const double z0 = std::sqrt(2 * tail / e_mu);
    if (!(x < mu) || x < mu - z0) x = mu - z0;
  }
  double lo = -30, hi = mu;
  if (!(x > lo && x < hi)) x = 0.5 * (std::max(lo, -6.0) + hi);
  const double target = std::log(upper ? tail : u * c_mu);
  for (int it = 0; it < 200; ++it) {
    const double c = mu * 0.5 * kSqrtPi * std::erfc(-x) + 0.5 * std::exp(-x * x);
    const double p = (mu - x) * std::exp(-x * x);
    double g, dg;
    if (!upper) {
      g = std::log(c) - target;
      dg = p / c;
    } else {
      const double s = c_mu - c;
      g = s > 0 ? std::log(s) - target : -1e300;
      dg = s > 0 ? -p / s : -1e300;
    }
    if (upper ? g < 0 : g > 0)  // x lies right of the root
      hi = x;
    else
      lo = x;
    const double xn = x - g / dg;
    if (std::abs(xn - x) <= 1e-8 * (1 + std::abs(x))) return std::clamp(xn, lo, hi);
    if (xn > lo && xn < hi) {
      x = xn;
    } else {
      x = 0.5 * (lo + hi);
      if (hi - lo <= 1e-14 * (1 + std::abs(x))) return x;
    }
  }
  return x;
}

}  // namespace

Eigen::Matrix3d rotation_x(double t) {
  Eigen::Matrix3d r;
  const double c = std::cos(t), s = std::sin(t);
  r << 1, 0, 0, 0, c, -s, 0, s, c;
  return r;
}
Eigen::Matrix3d rotation_y(double t) {
  Eigen::Matrix3d r;
  const double c = std::cos(t), s = std::sin(t);
  r << c, 0, s, 0, 1, 0, -s, 0, c;
  return r;
}
Eigen::Matrix3d rotation_z(double t) {
  Eigen::Matrix3d r;
  const double c = std::cos(t), s = std::sin(t);
  r << c, -s, 0, s, c, 0, 0, 0, 1;
  return r;
}

// ---------------------------------------------------------------------------------------------
double MicrofacetDistribution::G1(const Vec3& v) const {
  if (v.z() <= 0) return 0;
  return std::min(1.0, 1.0 / (1.0 + lambda(v)));
}

double MicrofacetDistribution::G1(const Vec3& v, const Vec3& m) const {
  if (v.dot(m) * v.z() <= 0) return 0;
  return G1(v);
}

double MicrofacetDistribution::G2(const Vec3& wi, const Vec3& wo, const Vec3& m,
                                  bool separable) const {
  if (wi.dot(m) * wi.z() <= 0 || wo.dot(m) * wo.z() <= 0 || wi.z() <= 0 || wo.z() <= 0) return 0;
  const double gi = G1(wi), go = G1(wo);
  if (separable) return gi * go;
  // Height-correlated 1/(1 + Lambda_i + Lambda_o) written with the clamped G1s, i.e. with Lambda
  // clamped to >= 0: identical for Beckmann/GGX (Lambda >= 0), and for a skewed ellipsoid it
  // keeps G2 <= min(G1_i, G1_o) so that the sampling weight F G2 (1 + Lambda_i) stays <= F.
  return 1.0 / (1.0 / gi + 1.0 / go - 1.0);
}

double MicrofacetDistribution::pdf_visible(const Vec3& v, const Vec3& m) const {
  if (v.z() <= 0) return 0;
  const double vm = v.dot(m);
  if (vm <= 0) return 0;
  return vm * D(m) / projected_area(v);
}

// ---------------------------------------------------------------------------------------------
BeckmannDistribution::BeckmannDistribution(double ax, double ay, double phi)
    : p_{ax, ay, phi}, c_(std::cos(phi)), s_(std::sin(phi)) {
  check_alpha(ax, ay);
}

double BeckmannDistribution::D(const Vec3& m) const {
  const double z = m.z();
  if (z <= 0) return 0;
  const double x = c_ * m.x() + s_ * m.y(), y = -s_ * m.x() + c_ * m.y();
  const double z2 = z * z;
  const double e = (x * x / (p_.alpha_x * p_.alpha_x) + y * y / (p_.alpha_y * p_.alpha_y)) / z2;
  return std::exp(-e) / (kPi * p_.alpha_x * p_.alpha_y * z2 * z2);
}

double BeckmannDistribution::lambda(const Vec3& v) const {
  const double x = c_ * v.x() + s_ * v.y(), y = -s_ * v.x() + c_ * v.y(), z = v.z();
  const double t2 =
      (p_.alpha_x * p_.alpha_x * x * x + p_.alpha_y * p_.alpha_y * y * y);  // alpha^2 tan^2 * z^2
  if (t2 <= 0) return 0;
  const double a = z / std::sqrt(t2);  // 1/(alpha tan theta)
  return -0.5 * std::erfc(a) + std::exp(-a * a) / (2 * a * kSqrtPi);
}

Vec3 BeckmannDistribution::sample_visible(const Vec3& v, double u1, double u2) const {
  // Local (rotated) frame, then stretch to the unit-roughness configuration.
  const double lx = c_ * v.x() + s_ * v.y(), ly = -s_ * v.x() + c_ * v.y();
  Vec3 vs(p_.alpha_x * lx, p_.alpha_y * ly, v.z());
  vs.normalize();
  const double sin_t = std::hypot(vs.x(), vs.y());
  const double mu = sin_t > 0 ? vs.z() / sin_t : std::numeric_limits<double>::infinity();
  const double cp = sin_t > 0 ? vs.x() / sin_t : 1, sp = sin_t > 0 ? vs.y() / sin_t : 0;
  // Slopes in the view-aligned unit configuration: x along the view azimuth.
  const double sx1 = sample_visible_slope(mu, u1);
  const double sy1 = sample_visible_slope(std::numeric_limits<double>::infinity(), u2);
  // Rotate to the view azimuth and unstretch.
  const double sx = p_.alpha_x * (cp * sx1 - sp * sy1);
  const double sy = p_.alpha_y * (sp * sx1 + cp * sy1);
  Vec3 ml(-sx, -sy, 1.0);
  ml.normalize();
  return Vec3(c_ * ml.x() - s_ * ml.y(), s_ * ml.x() + c_ * ml.y(), ml.z());
}

std::string BeckmannDistribution::describe() const {
  char e[48];
  std::snprintf(e, sizeof e, " phi=%.6g deg", p_.phi * 180 / kPi);
  return fmt_params("beckmann", p_.alpha_x, p_.alpha_y, e);
}

// ---------------------------------------------------------------------------------------------
GgxDistribution::GgxDistribution(double ax, double ay, double phi)
    : p_{ax, ay, phi}, c_(std::cos(phi)), s_(std::sin(phi)) {
  check_alpha(ax, ay);
}

double GgxDistribution::D(const Vec3& m) const {
  const double z = m.z();
  if (z <= 0) return 0;
  const double x = c_ * m.x() + s_ * m.y(), y = -s_ * m.x() + c_ * m.y();
  const double q = x * x / (p_.alpha_x * p_.alpha_x) + y * y / (p_.alpha_y * p_.alpha_y) + z * z;
  return 1.0 / (kPi * p_.alpha_x * p_.alpha_y * q * q);
}

double GgxDistribution::lambda(const Vec3& v) const {
  const double x = c_ * v.x() + s_ * v.y(), y = -s_ * v.x() + c_ * v.y(), z = v.z();
  const double t2 = (p_.alpha_x * p_.alpha_x * x * x + p_.alpha_y * p_.alpha_y * y * y) / (z * z);
  return 0.5 * (std::sqrt(1.0 + t2) - 1.0);
}

Vec3 GgxDistribution::sample_visible(const Vec3& v, double u1, double u2) const {
  const double lx = c_ * v.x() + s_ * v.y(), ly = -s_ * v.x() + c_ * v.y();
  Vec3 vh(p_.alpha_x * lx, p_.alpha_y * ly, v.z());
  vh.normalize();
  const Vec3 n = hemisphere_visible(vh, u1, u2);
  Vec3 ml(p_.alpha_x * n.x(), p_.alpha_y * n.y(), std::max(0.0, n.z()));
  ml.normalize();
  return Vec3(c_ * ml.x() - s_ * ml.y(), s_ * ml.x() + c_ * ml.y(), ml.z());
}

std::string GgxDistribution::describe() const {
  char e[48];
  std::snprintf(e, sizeof e, " phi=%.6g deg", p_.phi * 180 / kPi);
  return fmt_params("ggx", p_.alpha_x, p_.alpha_y, e);
}

// ---------------------------------------------------------------------------------------------
EllipsoidDistribution::EllipsoidDistribution(const EllipsoidParams& p) : p_(p) {
  check_alpha(p.alpha_x, p.alpha_y);
  for (double t : {p.theta_x, p.theta_y, p.theta_z})
    if (!std::isfinite(t)) throw InputError("ellipsoid rotation angles must be finite");
  r_ = rotation_x(p.theta_x) * rotation_y(p.theta_y) * rotation_z(p.theta_z);
  const Eigen::DiagonalMatrix<double, 3> s(p.alpha_x, p.alpha_y, 1.0);
  a_ = s * r_;
  ainvt_ = Eigen::DiagonalMatrix<double, 3>(1 / p.alpha_x, 1 / p.alpha_y, 1.0) *
           r_;  // (S R)^-T = S^-1 R
  an_ = a_.col(2);
  an_norm_ = an_.norm();
  det_ = p.alpha_x * p.alpha_y;
}

double EllipsoidDistribution::D(const Vec3& m) const {
  if (m.z() <= 0) return 0;
  const double q = (ainvt_ * m).squaredNorm();
  return 1.0 / (kPi * det_ * an_norm_ * q * q);
}

double EllipsoidDistribution::lambda(const Vec3& v) const {
  const Vec3 av = a_ * v;
  const double sigma = av.norm() / (2 * an_norm_) + av.dot(an_) / (2 * an_norm_ * an_norm_);
  return sigma / v.z() - 1.0;
}

Vec3 EllipsoidDistribution::sample_visible(const Vec3& v, double u1, double u2) const {
  // docs/theory.md §1.5: map the ellipsoid to the unit sphere (points A^-1 s), where uniform
  // projected area along v becomes uniform projected area along v' = Av/|Av|, and the cut
  // m.n > 0 becomes s.n' > 0 with n' = An/|An|.
  const Vec3 np = an_ / an_norm_;
  const Vec3 vp = (a_ * v).normalized();
  // Orthonormal frame (b1, b2, n').
  const Vec3 helper = std::abs(np.x()) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
  const Vec3 b1 = (helper - helper.dot(np) * np).normalized();
  const Vec3 b2 = np.cross(b1);
  const Vec3 vl(vp.dot(b1), vp.dot(b2), vp.dot(np));
  const Vec3 nl = hemisphere_visible(vl, u1, u2);
  const Vec3 s = nl.x() * b1 + nl.y() * b2 + nl.z() * np;
  return (a_.transpose() * s).normalized();
}

Vec3 EllipsoidDistribution::peak() const {
  Vec3 m = r_.transpose() * Vec3(0, 0, 1);
  return m.z() < 0 ? Vec3(-m) : m;
}

Vec3 EllipsoidDistribution::mean_normal() const {
  return a_.transpose() * an_ / (an_norm_ * an_norm_);
}

std::string EllipsoidDistribution::describe() const {
  char e[96];
  std::snprintf(e, sizeof e, " theta=(%.6g, %.6g, %.6g) deg", p_.theta_x * 180 / kPi,
                p_.theta_y * 180 / kPi, p_.theta_z * 180 / kPi);
  return fmt_params("ellipsoid", p_.alpha_x, p_.alpha_y, e);
}

// ---------------------------------------------------------------------------------------------
TabulatedNdf tabulate(const MicrofacetDistribution& d, const std::string& model,
                      std::size_t resolution, const NdfWindow& window) {
  if (resolution < 3) throw InputError("NDF table resolution must be at least 3");
  TabulatedNdf t(resolution, window);
  for (std::size_t iy = 0; iy < resolution; ++iy)
    for (std::size_t ix = 0; ix < resolution; ++ix) {
      const double x = t.node_x(ix), y = t.node_y(iy), r2 = x * x + y * y;
      t.at(ix, iy) = r2 < 1 ? d.D(Vec3(x, y, std::sqrt(1 - r2))) : 0.0;
    }
  const double raw = t.integral();
  t.normalise();
  t.meta.method = model;
  t.meta.sampling = "point";
  char b[64];
  std::snprintf(b, sizeof b, "; node sum before normalising %.9g", raw);
  t.meta.notes = d.describe() + b;
  return t;
}

std::shared_ptr<MicrofacetDistribution> make_distribution(const NdfSpec& s) {
  std::string m = s.model;
  std::transform(m.begin(), m.end(), m.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (m == "beckmann" || m == "ggx" || m == "trowbridge-reitz" || m == "gtr2") {
    if (s.theta_x != 0 || s.theta_y != 0 || s.theta_z != 0)
      throw InputError("--theta-x/--theta-y/--theta-z belong to the ellipsoid model; " + m +
                       " takes an in-plane rotation --phi");
    if (m == "beckmann") return std::make_shared<BeckmannDistribution>(s.alpha_x, s.alpha_y, s.phi);
    return std::make_shared<GgxDistribution>(s.alpha_x, s.alpha_y, s.phi);
  }
  if (m == "ellipsoid") {
    if (s.phi != 0)
      throw InputError("the ellipsoid model turns its axes with --theta-z, not --phi");
    return std::make_shared<EllipsoidDistribution>(
        EllipsoidParams{s.alpha_x, s.alpha_y, s.theta_x, s.theta_y, s.theta_z});
  }
  throw InputError("unknown NDF model '" + s.model + "' (known: beckmann, ggx, ellipsoid)");
}

}  // namespace microbrdf
