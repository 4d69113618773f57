#pragma once
// The ideal mirror.

#include <memory>
#include <optional>
#include <string>

#include "microbrdf/brdf.hpp"
#include "microbrdf/fresnel.hpp"

namespace microbrdf {

/// An ideal mirror (a delta lobe): eval() and pdf() are 0, sample() returns the mirror direction
/// with delta = true, pdf 0 and weight F(cos theta_i) (F = 1 without a Fresnel term).
class SpecularMirrorBrdf final : public Brdf {
 public:
  explicit SpecularMirrorBrdf(std::shared_ptr<const Fresnel> f = nullptr) : f_(std::move(f)) {}
  double eval(const Vec3&, const Vec3&, double) const override { return 0; }
  std::optional<BrdfSample> sample(const Vec3& wi, double u1, double u2,
                                   double wavelength_m) const override;
  double pdf(const Vec3&, const Vec3&) const override { return 0; }
  /// F(cos theta_i) (the whole reflected energy goes to the mirror direction).
  double albedo(const Vec3& wi, double wavelength_m) const override;
  Lobes lobes() const override { return {true, false, false}; }
  std::string describe() const override;

 private:
  std::shared_ptr<const Fresnel> f_;
};

}  // namespace microbrdf
