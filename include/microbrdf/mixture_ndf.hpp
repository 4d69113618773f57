#pragma once
// A two-lobe microfacet distribution: D = w D1 + (1 - w) D2 (a narrow core plus a wide tail, or
// any two models), with its exact Smith Lambda and sampling. Conventions as in microfacet.hpp.

#include <memory>
#include <string>

#include "microbrdf/microfacet.hpp"

namespace microbrdf {

/// w D1 + (1 - w) D2, w in [0, 1] the weight of the first lobe. Normalised when both lobes are.
///
/// - lambda(v) = w Lambda1(v) + (1 - w) Lambda2(v) exactly: sigma+(v) = integral D <v.m>+ dw is
///   linear in D, so sigma+ = w sigma1+ + (1 - w) sigma2+, and Lambda = sigma+/(v.n) - 1 with
///   w + (1 - w) = 1 absorbing the -1. (G1 = 1/(1 + Lambda) is therefore *not* the mixture of
///   the lobes' G1.) A lobe of weight 0 is skipped, so its infinite Lambda cannot give 0 * inf.
/// - sample_visible(v, u1, u2) picks lobe 1 with probability P1 = w sigma1+(v)/sigma+(v) (u1
///   decides and is rescaled to [0, 1)), then draws from that lobe; sampling_pdf(v, m) =
///   P1 q1(v, m) + (1 - P1) q2(v, m) with q_i the lobes' own sampling_pdf. When both lobes draw
///   their visible normals this is pdf_visible of the mixture exactly; it stays the true density
///   of the draws when a lobe samples something else (a tabulated NDF draws an approximation).
class MixtureDistribution final : public MicrofacetDistribution {
 public:
  /// Throws InputError for a null lobe or w outside [0, 1].
  MixtureDistribution(std::shared_ptr<const MicrofacetDistribution> first,
                      std::shared_ptr<const MicrofacetDistribution> second, double weight);
  double D(const Vec3& m) const override;
  double lambda(const Vec3& v) const override;
  Vec3 sample_visible(const Vec3& v, double u1, double u2) const override;
  double sampling_pdf(const Vec3& v, const Vec3& m) const override;
  bool samples_visible_exactly() const override {
    return first_->samples_visible_exactly() && second_->samples_visible_exactly();
  }
  /// "mixture w=0.3 of [ggx alpha=...] + [beckmann alpha=...]".
  std::string describe() const override;
  const MicrofacetDistribution& first() const { return *first_; }
  const MicrofacetDistribution& second() const { return *second_; }
  double weight() const { return w_; }
  /// P1 above: the probability that sample_visible(v, ...) draws from the first lobe.
  double first_lobe_probability(const Vec3& v) const;

 private:
  std::shared_ptr<const MicrofacetDistribution> first_, second_;
  double w_;
};

}  // namespace microbrdf
