#pragma once
// Sun 2002's analytic BRDF (sun2002.hpp) behind the Brdf interface.

#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "microbrdf/brdf.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/microfacet.hpp"
#include "microbrdf/sun2002.hpp"

namespace microbrdf::sun2002 {

/// Sun's BRDF behind the shared Brdf interface: eval() is sun2002::brdf(). Sampling draws h from
/// the visible normals of wi for the Beckmann distribution of the same surface (alpha = 2/s,
/// exact, BeckmannDistribution::sample_visible) and reflects: pdf(wo) = D_wi(h) / (4 wi.h),
/// weight = f cos(theta_o) / pdf (for the standard form this is
/// R Gamma_0(th_i) Gamma_0(th_o) sigma+(wi) / (wi.n), <= R Gamma_0 Gamma_0 / G1(wi)). Samples
/// below the horizon are dropped (no sample). `ftp` leaves out free travel probabilities as in
/// the rows of Sun's Fig. 8 (the sampling is the same).
/// One importance sample of Sun's BRDF (and of its textured form): a visible normal of the
/// Beckmann distribution d of Sun's slope variance (alpha = 2 / s), mirrored; `eval(wo)` gives
/// f(wi, wo) for the weight f cos / pdf. No sample when wi or wo is below the horizon.
std::optional<BrdfSample> sample_visible_beckmann(const BeckmannDistribution& d, const Vec3& wi,
                                                  double u1, double u2,
                                                  const std::function<double(const Vec3&)>& eval);
/// The density of sample_visible_beckmann, per steradian of wo (0 below the horizon).
double pdf_visible_beckmann(const BeckmannDistribution& d, const Vec3& wi, const Vec3& wo);

class SunBrdf final : public Brdf {
 public:
  /// s > 0 (InputError otherwise); a null Fresnel means R = 1.
  explicit SunBrdf(double s, BrdfForm form = BrdfForm::Standard,
                   std::shared_ptr<const Fresnel> f = nullptr, FtpTerms ftp = FtpTerms::Both);
  double eval(const Vec3& wi, const Vec3& wo, double wavelength_m) const override;
  std::optional<BrdfSample> sample(const Vec3& wi, double u1, double u2,
                                   double wavelength_m) const override;
  double pdf(const Vec3& wi, const Vec3& wo) const override;
  std::string describe() const override;
  double smoothness() const { return s_; }
  BrdfForm form() const { return form_; }
  FtpTerms ftp_terms() const { return ftp_; }
  const Fresnel* fresnel() const { return f_.get(); }

 private:
  double s_;
  BrdfForm form_;
  FtpTerms ftp_;
  std::shared_ptr<const Fresnel> f_;
  BeckmannDistribution d_;
};

}  // namespace microbrdf::sun2002
