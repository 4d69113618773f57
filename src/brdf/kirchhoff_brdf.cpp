// The Kirchhoff BRDF (Dong 2015 eq. 8) on tabulated D_K; see include/microbrdf/kirchhoff_brdf.hpp.
#include "microbrdf/kirchhoff_brdf.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "microbrdf/ndf_sampler.hpp"

namespace microbrdf {

KirchhoffBrdf::KirchhoffBrdf(std::vector<TabulatedNdf> tables,
                             std::shared_ptr<const Fresnel> fresnel,
                             std::shared_ptr<const MicrofacetDistribution> shadowing)
    : tables_(std::move(tables)), f_(std::move(fresnel)), g_(std::move(shadowing)) {
  if (tables_.empty() || !f_)
    throw std::invalid_argument("KirchhoffBrdf needs at least one D_K table and a Fresnel term");
  for (const auto& t : tables_)
    if (!(t.meta.wavelength_m > 0) && tables_.size() > 1)
      throw std::invalid_argument(
          "KirchhoffBrdf: every table needs its lambda_q (meta.wavelength_m)");
  std::sort(tables_.begin(), tables_.end(), [](const TabulatedNdf& a, const TabulatedNdf& b) {
    return a.meta.wavelength_m < b.meta.wavelength_m;
  });
  double best = INFINITY;
  for (std::size_t i = 0; i < tables_.size(); ++i) {
    double d = std::fabs(tables_[i].meta.wavelength_m - 555e-9);
    if (d < best) {
      best = d;
      sample_table_ = i;
    }
  }
  sampler_ = std::make_shared<NdfSampler>(tables_[sample_table_]);
}

double KirchhoffBrdf::dk(const Vec3& h, double lambda_q) const {
  if (tables_.size() == 1) return tables_[0].eval(h);
  // Linear in 1/lambda_q (i.e. in |q|) between the bracketing tables, clamped at the ends.
  if (lambda_q <= tables_.front().meta.wavelength_m) return tables_.front().eval(h);
  if (lambda_q >= tables_.back().meta.wavelength_m) return tables_.back().eval(h);
  std::size_t i = 1;
  while (tables_[i].meta.wavelength_m < lambda_q) ++i;
  double a = 1 / tables_[i - 1].meta.wavelength_m, b = 1 / tables_[i].meta.wavelength_m;
  double u = (1 / lambda_q - a) / (b - a);
  return (1 - u) * tables_[i - 1].eval(h) + u * tables_[i].eval(h);
}

double KirchhoffBrdf::eval(const Vec3& wi, const Vec3& wo, double wavelength_m) const {
  if (wi.z() <= 0 || wo.z() <= 0) return 0;
  const Vec3 hs = wi + wo;
  const double len = hs.norm();
  if (len == 0) return 0;
  const Vec3 h = hs / len;
  const double lambda_q = 2 * wavelength_m / len;  // eq. 5
  const double g = g_ ? g_->G2(wi, wo, h) : 1.0;
  if (g == 0) return 0;
  return dk(h, lambda_q) * f_->eval(wi.dot(h), wavelength_m) * g / (4 * wi.z() * wo.z());
}

std::optional<BrdfSample> KirchhoffBrdf::sample(const Vec3& wi, double u1, double u2,
                                                double wavelength_m) const {
  if (wi.z() <= 0) return std::nullopt;
  const auto& s = *static_cast<const NdfSampler*>(sampler_.get());
  const Vec3 h = s.sample(u1, u2);
  const double ih = wi.dot(h);
  if (ih <= 0) return std::nullopt;
  const Vec3 wo = 2 * ih * h - wi;
  if (wo.z() <= 0) return std::nullopt;
  BrdfSample out;
  out.wo = wo;
  out.pdf = pdf(wi, wo);
  if (!(out.pdf > 0)) return std::nullopt;
  out.weight = eval(wi, wo, wavelength_m) * wo.z() / out.pdf;
  return out;
}

double KirchhoffBrdf::pdf(const Vec3& wi, const Vec3& wo) const {
  const auto hv = reflection_half_vector(wi, wo);
  if (!hv) return 0;
  const auto& s = *static_cast<const NdfSampler*>(sampler_.get());
  return s.pdf(hv->h) / (4 * hv->wi_dot_h);
}

std::string KirchhoffBrdf::describe() const {
  std::ostringstream o;
  o << "Kirchhoff (Dong eq. 8): D_K at lambda_q =";
  for (const auto& t : tables_) o << " " << t.meta.wavelength_m * 1e9 << "nm";
  o << ", " << f_->describe() << ", "
    << (g_ ? "Smith G2 of " + g_->describe() : std::string("no shadowing (G = 1)"));
  return o.str();
}

}  // namespace microbrdf
