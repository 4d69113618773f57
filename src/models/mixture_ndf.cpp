// Two-lobe mixture of microfacet distributions (include/microbrdf/mixture_ndf.hpp).
#include "microbrdf/mixture_ndf.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "microbrdf/error.hpp"

namespace microbrdf {
namespace {
const double kBelowOne = std::nextafter(1.0, 0.0);  // the largest u below 1
}  // namespace

MixtureDistribution::MixtureDistribution(std::shared_ptr<const MicrofacetDistribution> first,
                                         std::shared_ptr<const MicrofacetDistribution> second,
                                         double weight)
    : first_(std::move(first)), second_(std::move(second)), w_(weight) {
  if (!first_ || !second_) throw InputError("mixture: both lobes must be given");
  if (!(weight >= 0 && weight <= 1)) throw InputError("mixture: weight must lie in [0, 1]");
}

double MixtureDistribution::D(const Vec3& m) const {
  const double d1 = w_ > 0 ? first_->D(m) : 0, d2 = w_ < 1 ? second_->D(m) : 0;
  return w_ * d1 + (1 - w_) * d2;
}

double MixtureDistribution::lambda(const Vec3& v) const {
  // sigma+ is linear in D (see the header); skipping a weightless lobe avoids 0 * inf.
  const double l1 = w_ > 0 ? w_ * first_->lambda(v) : 0;
  const double l2 = w_ < 1 ? (1 - w_) * second_->lambda(v) : 0;
  return l1 + l2;
}

double MixtureDistribution::first_lobe_probability(const Vec3& v) const {
  if (w_ <= 0 || w_ >= 1) return w_;
  const double s1 = w_ * first_->projected_area(v), s2 = (1 - w_) * second_->projected_area(v);
  // A lobe with infinite projected area (Student-t, gamma <= 1.5) takes every visible sample.
  if (std::isinf(s1) || std::isinf(s2))
    return std::isinf(s1) && std::isinf(s2) ? w_ : (std::isinf(s1) ? 1.0 : 0.0);
  // v.z <= 0 has no visible normals; fall back to the weights.
  return s1 + s2 > 0 ? s1 / (s1 + s2) : w_;
}

Vec3 MixtureDistribution::sample_visible(const Vec3& v, double u1, double u2) const {
  const double p1 = first_lobe_probability(v);
  // u1 < p1 picks the first lobe; rescaled, u1 is again uniform on [0, 1) for that lobe.
  if (u1 < p1) return first_->sample_visible(v, std::min(u1 / p1, kBelowOne), u2);
  return second_->sample_visible(v, std::min((u1 - p1) / (1 - p1), kBelowOne), u2);
}

double MixtureDistribution::sampling_pdf(const Vec3& v, const Vec3& m) const {
  const double p1 = first_lobe_probability(v);
  const double q1 = p1 > 0 ? p1 * first_->sampling_pdf(v, m) : 0;
  const double q2 = p1 < 1 ? (1 - p1) * second_->sampling_pdf(v, m) : 0;
  return q1 + q2;
}

std::string MixtureDistribution::describe() const {
  char w[32];
  std::snprintf(w, sizeof w, "%.6g", w_);
  return std::string("mixture w=") + w + " of [" + first_->describe() + "] + [" +
         second_->describe() + "]";
}

}  // namespace microbrdf
