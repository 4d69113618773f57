// The Lambertian BRDF (include/microbrdf/lambertian_brdf.hpp).
#include "microbrdf/lambertian_brdf.hpp"

#include <algorithm>
#include <cmath>

#include "microbrdf/error.hpp"

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

double LambertianBrdf::albedo(const Vec3& wi, double) const { return wi.z() > 0 ? albedo_ : 0.0; }

std::string LambertianBrdf::describe() const {
  return "Lambertian albedo " + std::to_string(albedo_);
}

}  // namespace microbrdf
