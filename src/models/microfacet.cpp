// Beckmann, GGX and ellipsoid microfacet distributions (include/microbrdf/microfacet.hpp).
#include "microbrdf/microfacet.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "microbrdf/error.hpp"
#include "models/beckmann_math.hpp"

namespace microbrdf {
namespace {

constexpr double kPi = 3.14159265358979323846;

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
    : p_{ax, ay, phi},
      c_(std::cos(phi)),
      s_(std::sin(phi)),
      inv_ax2_(1 / (ax * ax)),
      inv_ay2_(1 / (ay * ay)),
      d_norm_(1 / (kPi * ax * ay)) {
  check_alpha(ax, ay);
}

double BeckmannDistribution::D(const Vec3& m) const {
  const double z = m.z();
  if (z <= 0) return 0;
  const double x = c_ * m.x() + s_ * m.y(), y = -s_ * m.x() + c_ * m.y();
  const double iz2 = 1 / (z * z);
  const double e = (x * x * inv_ax2_ + y * y * inv_ay2_) * iz2;
  return std::exp(-e) * d_norm_ * iz2 * iz2;
}

double BeckmannDistribution::lambda(const Vec3& v) const {
  const double x = c_ * v.x() + s_ * v.y(), y = -s_ * v.x() + c_ * v.y(), z = v.z();
  const double t2 =
      (p_.alpha_x * p_.alpha_x * x * x + p_.alpha_y * p_.alpha_y * y * y);  // alpha^2 tan^2 * z^2
  // a = 1/(alpha tan theta); Lambda(5.75) < 4e-18: 0 beyond (1 + Lambda rounds to 1 there)
  if (!(z * z > 33.0625 * t2)) return t2 > 0 ? beckmann::smith_lambda(z / std::sqrt(t2)) : 0.0;
  return 0;
}

Vec3 BeckmannDistribution::sample_visible(const Vec3& v, double u1, double u2) const {
  // Local (rotated) frame, then stretch to the unit-roughness configuration.
  const double lx = c_ * v.x() + s_ * v.y(), ly = -s_ * v.x() + c_ * v.y();
  const double vx = p_.alpha_x * lx, vy = p_.alpha_y * ly;
  const double r2 = vx * vx + vy * vy;
  const double ir = 1 / std::sqrt(r2);  // no overflow: |v| = 1, alphas <= 10; inf for r2 = 0
  const bool tilted = r2 > 0;
  const double mu = tilted ? v.z() * ir : std::numeric_limits<double>::infinity();
  const double cp = tilted ? vx * ir : 1, sp = tilted ? vy * ir : 0;
  // Slopes in the view-aligned unit configuration: x along the view azimuth.
  const double sx1 = beckmann::visible_slope(mu, u1);
  const double sy1 = beckmann::gauss_quantile(u2);
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
  np_ = an_ / an_norm_;
  const Vec3 helper = std::abs(np_.x()) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
  b1_ = (helper - helper.dot(np_) * np_).normalized();
  b2_ = np_.cross(b1_);
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
  // Orthonormal frame (b1, b2, n'), fixed per distribution (constructor).
  const Vec3 vp = (a_ * v).normalized();
  const Vec3 vl(vp.dot(b1_), vp.dot(b2_), vp.dot(np_));
  const Vec3 nl = hemisphere_visible(vl, u1, u2);
  const Vec3 s = nl.x() * b1_ + nl.y() * b2_ + nl.z() * np_;
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

}  // namespace microbrdf
