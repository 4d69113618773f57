#pragma once
// The ideal diffuse reflector.

#include <optional>
#include <string>

#include "microbrdf/brdf.hpp"

namespace microbrdf {

/// A Lambertian reflector f = albedo / pi (furnace tests, diffuse props, the exact reference of
/// the SH estimator, docs/theory.md §6.3); cosine-weighted sampling, weight = albedo. Lobes:
/// diffuse.
class LambertianBrdf final : public Brdf {
 public:
  /// albedo in [0, 1] (InputError otherwise).
  explicit LambertianBrdf(double albedo = 1.0);
  double eval(const Vec3& wi, const Vec3& wo, double wavelength_m) const override;
  std::optional<BrdfSample> sample(const Vec3& wi, double u1, double u2,
                                   double wavelength_m) const override;
  double pdf(const Vec3& wi, const Vec3& wo) const override;
  double albedo(const Vec3& wi, double wavelength_m) const override;
  Lobes lobes() const override { return {false, false, true}; }
  std::string describe() const override;
  double albedo() const { return albedo_; }

 private:
  double albedo_;
};

}  // namespace microbrdf
