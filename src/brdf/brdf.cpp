// What every BRDF shares (include/microbrdf/brdf.hpp): the half vector and the default albedo.
#include "microbrdf/brdf.hpp"

#include "microbrdf/brdf_albedo.hpp"

namespace microbrdf {

double Brdf::albedo(const Vec3& wi, double wavelength_m) const {
  return directional_albedo_sampled(*this, wi, wavelength_m, 256);
}

std::optional<HalfVector> reflection_half_vector(const Vec3& wi, const Vec3& wo) {
  if (wi.z() <= 0 || wo.z() <= 0) return std::nullopt;
  const Vec3 hs = wi + wo;
  const double len = hs.norm();
  if (len == 0) return std::nullopt;
  const Vec3 h = hs / len;
  const double ih = wi.dot(h);
  if (ih <= 0) return std::nullopt;
  return HalfVector{h, ih};
}

}  // namespace microbrdf
