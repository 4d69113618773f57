#pragma once
// The microfacet BRDF (Dong 2015 eq. 1) over any distribution of micro-normals.

#include <memory>
#include <optional>
#include <string>

#include "microbrdf/brdf.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/microfacet.hpp"

namespace microbrdf {

/// Dong 2015 eq. 1: f = F(wi.h) D(h) G(wi, wo) / (4 |wi.n| |wo.n|), h = (wi + wo)/|wi + wo|.
/// G is Smith's height-correlated G2 by default; `separable_g` gives G1(wi) G1(wo) (Dong eq. 13).
/// Sampling draws h with the distribution's sample_visible (the visible normals of wi for the
/// analytic models) and reflects: pdf = q(h) / (4 wi.h) with q = sampling_pdf(wi, h) (D_wi(h)
/// for visible normals, then weight = F G2 / G1u(wi)); weight = F D G2 (wi.h) / ((wi.n) q).
class MicrofacetBrdf final : public Brdf {
 public:
  MicrofacetBrdf(std::shared_ptr<const MicrofacetDistribution> d, std::shared_ptr<const Fresnel> f,
                 bool separable_g = false);
  double eval(const Vec3& wi, const Vec3& wo, double wavelength_m) const override;
  std::optional<BrdfSample> sample(const Vec3& wi, double u1, double u2,
                                   double wavelength_m) const override;
  double pdf(const Vec3& wi, const Vec3& wo) const override;
  std::string describe() const override;
  const MicrofacetDistribution& distribution() const { return *d_; }
  const Fresnel& fresnel() const { return *f_; }
  bool separable_g() const { return separable_; }

 private:
  std::shared_ptr<const MicrofacetDistribution> d_;
  std::shared_ptr<const Fresnel> f_;
  bool separable_;
};

}  // namespace microbrdf
