// The microfacet BRDF (include/microbrdf/microfacet_brdf.hpp, Dong 2015 eq. 1).
#include "microbrdf/microfacet_brdf.hpp"

#include <cmath>
#include <stdexcept>

namespace microbrdf {
namespace {
constexpr double kPi = 3.14159265358979323846;
}

MicrofacetBrdf::MicrofacetBrdf(std::shared_ptr<const MicrofacetDistribution> d,
                               std::shared_ptr<const Fresnel> f, bool separable_g)
    : d_(std::move(d)), f_(std::move(f)), separable_(separable_g) {
  if (!d_ || !f_)
    throw std::invalid_argument("MicrofacetBrdf needs a distribution and a Fresnel term");
}

double MicrofacetBrdf::eval(const Vec3& wi, const Vec3& wo, double wavelength_m) const {
  if (wi.z() <= 0 || wo.z() <= 0) return 0;
  const Vec3 hs = wi + wo;
  const double len = hs.norm();
  if (len == 0) return 0;
  const Vec3 h = hs / len;
  const double g = d_->G2(wi, wo, h, separable_);
  if (g == 0) return 0;
  return f_->eval(wi.dot(h), wavelength_m) * d_->D(h) * g / (4 * wi.z() * wo.z());
}

std::optional<BrdfSample> MicrofacetBrdf::sample(const Vec3& wi, double u1, double u2,
                                                 double wavelength_m) const {
  if (wi.z() <= 0) return std::nullopt;
  const Vec3 m = d_->sample_visible(wi, u1, u2);
  const double im = wi.dot(m);
  if (im <= 0) return std::nullopt;
  const Vec3 wo = 2 * im * m - wi;
  if (wo.z() <= 0) return std::nullopt;
  BrdfSample s;
  s.wo = wo;
  const double q = d_->sampling_pdf(wi, m);  // density of m per steradian
  s.pdf = q / (4 * im);
  if (!(s.pdf > 0)) return std::nullopt;
  // f cos / pdf = F D G2 / (4 wi.z) * 4 (wi.m) / q. With visible normals, q = (wi.m) D /
  // sigma+(wi) and this is F G2 sigma+(wi) / wi.z.
  const double g = d_->G2(wi, wo, m, separable_);
  s.weight = f_->eval(im, wavelength_m) * g * d_->D(m) * im / (wi.z() * q);
  return s;
}

double MicrofacetBrdf::pdf(const Vec3& wi, const Vec3& wo) const {
  const auto hv = reflection_half_vector(wi, wo);
  return hv ? d_->sampling_pdf(wi, hv->h) / (4 * hv->wi_dot_h) : 0.0;
}

std::string MicrofacetBrdf::describe() const {
  return "microfacet (Dong eq. 1): " + d_->describe() + ", " + f_->describe() +
         (separable_ ? ", separable Smith G1 G1" : ", height-correlated Smith G2");
}

}  // namespace microbrdf
