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
  for (std::size_t i = 1; i < tables_.size(); ++i)
    if (!(tables_[i].meta.wavelength_m > tables_[i - 1].meta.wavelength_m))
      throw std::invalid_argument("KirchhoffBrdf: two D_K tables at lambda_q " +
                                  std::to_string(tables_[i].meta.wavelength_m * 1e9) + " nm");
  for (const auto& t : tables_) log_lq_.push_back(std::log(t.meta.wavelength_m));
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
  const std::size_t n = tables_.size();
  if (n == 1) return tables_[0].eval(h);
  // Outside the stack: the nearest table (docs/kirchhoff.md "lambda_q per direction").
  if (lambda_q <= tables_.front().meta.wavelength_m) return tables_.front().eval(h);
  if (lambda_q >= tables_.back().meta.wavelength_m) return tables_.back().eval(h);
  const double x = std::log(lambda_q);
  std::size_t k = 1;
  while (log_lq_[k] < x) ++k;
  --k;  // x in [x_k, x_k+1]
  // At a fixed half-vector D_K is smooth in log lambda_q (a power-law spectrum is a straight
  // line in log D vs log |q|, a Gaussian one a parabola in |q|): cubic Lagrange interpolation of
  // log D through the four nearest tables (three or two at the ends of the stack). A zero among
  // them (outside the disk, the Nyquist mask) falls back to linear interpolation of D.
  const std::size_t lo = k == 0 ? 0 : k - 1, hi = std::min(k + 2, n - 1);
  double y[4];
  bool positive = true;
  for (std::size_t i = lo; i <= hi; ++i) {
    y[i - lo] = tables_[i].eval(h);
    positive = positive && y[i - lo] > 0;
  }
  if (!positive) {
    const double u = (x - log_lq_[k]) / (log_lq_[k + 1] - log_lq_[k]);
    return (1 - u) * y[k - lo] + u * y[k + 1 - lo];
  }
  double logd = 0;
  for (std::size_t i = lo; i <= hi; ++i) {
    double w = 1;
    for (std::size_t j = lo; j <= hi; ++j)
      if (j != i) w *= (x - log_lq_[j]) / (log_lq_[i] - log_lq_[j]);
    logd += w * std::log(y[i - lo]);
  }
  return std::exp(logd);
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
  o << "Kirchhoff (Dong eq. 8): D_K ";
  if (tables_.size() == 1)
    o << "at lambda_q = " << tables_[0].meta.wavelength_m * 1e9
      << "nm for every direction (one table)";
  else
    o << "interpolated at each direction's lambda_q from " << tables_.size() << " tables, "
      << tables_.front().meta.wavelength_m * 1e9 << ".." << tables_.back().meta.wavelength_m * 1e9
      << "nm";
  o << ", " << f_->describe() << ", "
    << (g_ ? "Smith G2 of " + g_->describe() : std::string("no shadowing (G = 1)"));
  return o.str();
}

}  // namespace microbrdf
