// Sun 2002's BRDF behind the Brdf interface (include/microbrdf/sun_brdf.hpp).
#include "microbrdf/sun_brdf.hpp"

#include <cmath>
#include <string>

#include "microbrdf/error.hpp"

namespace microbrdf::sun2002 {

namespace {
double checked_s(double s) {
  if (!(s > 0) || !std::isfinite(s))
    throw InputError("Sun 2002 BRDF: smoothness s must be positive, got " + std::to_string(s));
  return s;
}
}  // namespace

SunBrdf::SunBrdf(double s, BrdfForm form, std::shared_ptr<const Fresnel> f, FtpTerms ftp)
    : s_(checked_s(s)), form_(form), ftp_(ftp), f_(std::move(f)), d_(2 / checked_s(s)) {}

double SunBrdf::eval(const Vec3& wi, const Vec3& wo, double wavelength_m) const {
  return brdf(wi, wo, s_, form_, f_.get(), wavelength_m, ftp_);
}

std::optional<BrdfSample> sample_visible_beckmann(const BeckmannDistribution& d, const Vec3& wi,
                                                  double u1, double u2,
                                                  const std::function<double(const Vec3&)>& eval) {
  if (!(wi.z() > 0)) return std::nullopt;
  const Vec3 m = d.sample_visible(wi, u1, u2);
  const double im = wi.dot(m);
  if (!(im > 0)) return std::nullopt;
  const Vec3 wo = 2 * im * m - wi;
  if (!(wo.z() > 0)) return std::nullopt;
  BrdfSample r;
  r.wo = wo;
  r.pdf = d.pdf_visible(wi, m) / (4 * im);  // Jacobian of the mirror map, d omega_o / d omega_m
  if (!(r.pdf > 0)) return std::nullopt;
  r.weight = eval(wo) * wo.z() / r.pdf;
  return r;
}

std::optional<BrdfSample> SunBrdf::sample(const Vec3& wi, double u1, double u2,
                                          double wavelength_m) const {
  return sample_visible_beckmann(d_, wi, u1, u2,
                                 [&](const Vec3& wo) { return eval(wi, wo, wavelength_m); });
}

double pdf_visible_beckmann(const BeckmannDistribution& d, const Vec3& wi, const Vec3& wo) {
  if (!(wi.z() > 0) || !(wo.z() > 0)) return 0;
  const Vec3 hs = wi + wo;
  const double len = hs.norm();
  if (!(len > 0)) return 0;
  const Vec3 h = hs / len;
  const double ih = wi.dot(h);
  if (!(ih > 0)) return 0;
  return d.pdf_visible(wi, h) / (4 * ih);
}

double SunBrdf::pdf(const Vec3& wi, const Vec3& wo) const {
  return pdf_visible_beckmann(d_, wi, wo);
}

std::string SunBrdf::describe() const {
  return "Sun 2002 eq. 3.5.3 (" +
         std::string(form_ == BrdfForm::AsPublished ? "as published" : "standard microfacet form") +
         "), s = " + std::to_string(s_) +
         (ftp_ == FtpTerms::Both ? std::string()
                                 : ", free travel probabilities: " + ftp_terms_name(ftp_)) +
         ", " + (f_ ? f_->describe() : std::string("R = 1"));
}

}  // namespace microbrdf::sun2002
