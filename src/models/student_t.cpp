// The Student-t microfacet distribution (include/microbrdf/student_t.hpp).
#include "microbrdf/student_t.hpp"

#include <cstdio>
#include <limits>

#include "microbrdf/error.hpp"
#include "models/student_t_math.hpp"

namespace microbrdf {

StudentTDistribution::StudentTDistribution(const StudentTParams& p)
    : p_(p), c_(std::cos(p.phi)), s_(std::sin(p.phi)) {
  const bool alphas_ok = p.alpha_x > 0 && p.alpha_x <= 10 && p.alpha_y > 0 && p.alpha_y <= 10;
  if (!alphas_ok) throw InputError("student-t: roughness alpha must lie in (0, 10]");
  if (!std::isfinite(p.phi)) throw InputError("student-t: phi must be finite");
  if (!(p.gamma > kStudentTGammaMin && p.gamma <= kStudentTGammaMax))
    throw InputError("student-t: gamma must lie in (1, 1e6] (2 = GGX, large = Beckmann)");
  slopes_ = std::make_shared<const student_t::Slopes>(p.gamma);
}

double StudentTDistribution::D(const Vec3& m) const {
  const double z = m.z();
  if (z <= 0) return 0;
  const double x = c_ * m.x() + s_ * m.y(), y = -s_ * m.x() + c_ * m.y();
  if (z > 1e-60) return student_t_d(p_.alpha_x, p_.alpha_y, p_.gamma, x / z, y / z, z);
  // Within 1e-60 of the horizon (sampled slopes reach 1e150 when gamma is near 1) z^4 would
  // underflow: ln D = -gamma ln(z^2 + Q/a) + (2 gamma - 4) ln z - ln(pi ax ay),
  // Q = x^2/ax^2 + y^2/ay^2, a = gamma - 1.
  const double q = x * x / (p_.alpha_x * p_.alpha_x) + y * y / (p_.alpha_y * p_.alpha_y);
  const double g = p_.gamma;
  return std::exp(-g * std::log(z * z + q / (g - 1)) + (2 * g - 4) * std::log(z) -
                  std::log(3.14159265358979323846 * p_.alpha_x * p_.alpha_y));
}

double StudentTDistribution::lambda(const Vec3& v) const {
  const double x = c_ * v.x() + s_ * v.y(), y = -s_ * v.x() + c_ * v.y();
  // alpha_v^2 tan^2 theta_v * z^2, as for GGX
  const double t2 = p_.alpha_x * p_.alpha_x * x * x + p_.alpha_y * p_.alpha_y * y * y;
  if (!(t2 > 0)) return 0;
  return slopes_->lambda(v.z() / std::sqrt(t2));
}

Vec3 StudentTDistribution::sample_visible(const Vec3& v, double u1, double u2) const {
  // Local (rotated) frame, then stretch to the unit-roughness configuration.
  const double lx = c_ * v.x() + s_ * v.y(), ly = -s_ * v.x() + c_ * v.y();
  const double vx = p_.alpha_x * lx, vy = p_.alpha_y * ly;
  const double r2 = vx * vx + vy * vy;
  // gamma <= 1.5 off the normal: no visible-normal density exists; D(m)(m.n) is drawn (the
  // stretched view's azimuth is then irrelevant, the slope density being isotropic).
  const bool tilted = r2 > 0 && slopes_->finite_lambda();
  const double ir = tilted ? 1 / std::sqrt(r2) : 0;
  const double mu = tilted ? v.z() * ir : std::numeric_limits<double>::infinity();
  const double cp = tilted ? vx * ir : 1, sp = tilted ? vy * ir : 0;
  // Slopes in the view-aligned unit configuration: x along the view azimuth.
  const double sx1 = slopes_->visible_slope(mu, u1);
  const double sy1 = slopes_->perpendicular_slope(sx1, u2);
  // Rotate to the view azimuth and unstretch.
  const double sx = p_.alpha_x * (cp * sx1 - sp * sy1);
  const double sy = p_.alpha_y * (sp * sx1 + cp * sy1);
  Vec3 ml(-sx, -sy, 1.0);
  ml.normalize();
  return Vec3(c_ * ml.x() - s_ * ml.y(), s_ * ml.x() + c_ * ml.y(), ml.z());
}

double StudentTDistribution::sampling_pdf(const Vec3& v, const Vec3& m) const {
  if (slopes_->finite_lambda() || (v.x() == 0 && v.y() == 0)) return pdf_visible(v, m);
  return pdf(m);
}

std::string StudentTDistribution::describe() const {
  char b[160];
  std::snprintf(b, sizeof b, "student-t alpha=(%.6g, %.6g) phi=%.6g deg gamma=%.6g", p_.alpha_x,
                p_.alpha_y, p_.phi * 180 / 3.14159265358979323846, p_.gamma);
  return b;
}

}  // namespace microbrdf
