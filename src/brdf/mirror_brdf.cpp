// The ideal mirror (include/microbrdf/mirror_brdf.hpp).
#include "microbrdf/mirror_brdf.hpp"

namespace microbrdf {

std::optional<BrdfSample> SpecularMirrorBrdf::sample(const Vec3& wi, double, double,
                                                     double wavelength_m) const {
  if (!(wi.z() > 0)) return std::nullopt;
  BrdfSample s;
  s.wo = Vec3(-wi.x(), -wi.y(), wi.z());
  s.pdf = 0;
  s.delta = true;
  s.weight = f_ ? f_->eval(wi.z(), wavelength_m) : 1.0;
  return s;
}

std::string SpecularMirrorBrdf::describe() const {
  return "ideal mirror" + (f_ ? ", " + f_->describe() : std::string(", F = 1"));
}

double SpecularMirrorBrdf::albedo(const Vec3& wi, double wavelength_m) const {
  if (!(wi.z() > 0)) return 0;
  return f_ ? f_->eval(wi.z(), wavelength_m) : 1.0;
}

}  // namespace microbrdf
