#pragma once
// The Kirchhoff BRDF (Dong 2015 eq. 8) over tables of D_K (kirchhoff.hpp computes them).

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "microbrdf/brdf.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/microfacet.hpp"
#include "microbrdf/tabulated_ndf.hpp"

namespace microbrdf {

/// Dong 2015 eq. 8: f = D_K(4 pi h / lambda_q) F(wi.h) G(wi, wo) / (4 |wi.n| |wo.n|).
/// - Several tables (a stack over lambda_q, as `ndf --method kirchhoff` writes by default): the
///   actual lambda_q = 2 lambda / |wi + wo| (eq. 5) is formed per evaluation and log D_K at the
///   half-vector is interpolated cubically in log lambda_q through the nearest four tables
///   (linearly in D_K where one of them is 0); outside the stack the nearest table is used.
/// - One table: D_K at its fixed lambda_q is used for every wavelength and direction (Dong
///   section 7). Right only where lambda_q is near that value (near-normal backscatter for a
///   table at the light's wavelength); single_table() lets callers warn.
/// G: Smith G2 of the `shadowing` distribution when one is given (e.g. a fitted Beckmann or
/// ellipsoid, as Dong does), else 1 (plain Kirchhoff, eq. 7). Sampling draws h from the table
/// closest to 555 nm (NdfSampler: density D(h)(h.n)) and reflects.
class KirchhoffBrdf final : public Brdf {
 public:
  KirchhoffBrdf(std::vector<TabulatedNdf> tables, std::shared_ptr<const Fresnel> fresnel,
                std::shared_ptr<const MicrofacetDistribution> shadowing = nullptr);
  KirchhoffBrdf(const KirchhoffBrdf&) = delete;  // the sampler points into tables_
  KirchhoffBrdf& operator=(const KirchhoffBrdf&) = delete;
  double eval(const Vec3& wi, const Vec3& wo, double wavelength_m) const override;
  std::optional<BrdfSample> sample(const Vec3& wi, double u1, double u2,
                                   double wavelength_m) const override;
  double pdf(const Vec3& wi, const Vec3& wo) const override;
  std::string describe() const override;
  /// D_K(h) at lambda_q (interpolated between tables as described above).
  double dk(const Vec3& h, double lambda_q) const;
  const std::vector<TabulatedNdf>& tables() const { return tables_; }
  /// One table for every direction (no lambda_q interpolation).
  bool single_table() const { return tables_.size() == 1; }

 private:
  std::vector<TabulatedNdf> tables_;  // sorted by lambda_q
  std::vector<double> log_lq_;        // log lambda_q of each table
  std::shared_ptr<const Fresnel> f_;
  std::shared_ptr<const MicrofacetDistribution> g_;
  std::size_t sample_table_ = 0;
  std::shared_ptr<const void> sampler_;  // NdfSampler of tables_[sample_table_]
};

}  // namespace microbrdf
