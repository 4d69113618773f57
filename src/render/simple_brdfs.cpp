// Lambertian and ideal-mirror BRDFs for furnace and mirror tests (render.hpp).
#include <cmath>

#include "microbrdf/error.hpp"
#include "microbrdf/render.hpp"

namespace microbrdf {

LambertianBrdf::LambertianBrdf(double albedo) : albedo_(albedo) {
  if (!(albedo >= 0 && albedo <= 1)) throw InputError("Lambertian albedo must lie in [0, 1]");
}

double LambertianBrdf::eval(const Vec3& wi, const Vec3& wo, double) const {
  return wi.z() > 0 && wo.z() > 0 ? albedo_ / M_PI : 0.0;
}

std::optional<BrdfSample> LambertianBrdf::sample(const Vec3& wi, double u1, double u2,
                                                 double) const {
  if (!(wi.z() > 0)) return std::nullopt;
  const double r = std::sqrt(u1), phi = 2 * M_PI * u2;
  const double z = std::sqrt(std::max(0.0, 1 - u1));
  if (!(z > 0)) return std::nullopt;
  BrdfSample s;
  s.wo = Vec3(r * std::cos(phi), r * std::sin(phi), z);
  s.pdf = z / M_PI;
  s.weight = albedo_;
  return s;
}

double LambertianBrdf::pdf(const Vec3& wi, const Vec3& wo) const {
  return wi.z() > 0 && wo.z() > 0 ? wo.z() / M_PI : 0.0;
}

std::string LambertianBrdf::describe() const {
  return "Lambertian albedo " + std::to_string(albedo_);
}

std::optional<BrdfSample> SpecularMirrorBrdf::sample(const Vec3& wi, double, double,
                                                     double wavelength_m) const {
  if (!(wi.z() > 0)) return std::nullopt;
  BrdfSample s;
  s.wo = Vec3(-wi.x(), -wi.y(), wi.z());
  s.pdf = 0;
  s.weight = f_ ? f_->eval(wi.z(), wavelength_m) : 1.0;
  return s;
}

std::string SpecularMirrorBrdf::describe() const {
  return "ideal mirror" + (f_ ? ", " + f_->describe() : std::string(", F = 1"));
}

}  // namespace microbrdf
