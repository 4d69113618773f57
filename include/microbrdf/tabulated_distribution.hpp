#pragma once
// A TabulatedNdf used as a microfacet distribution (theory notes sections 2.3 and 2.4).
//
//  - D(m) = TabulatedNdf::eval(m) / Z, Z = NdfSampler::normalisation() (the integral of the
//    bilinear interpolant over the disk), so that integral D(m)(m.n) dw = 1 exactly and D is the
//    very interpolant the sampler draws from.
//  - Smith / projected-area shadowing (Ashikhmin-Premoze-Shirley = Smith, Heitz 2014):
//      sigma+(k) = integral D(m) <k.m>+ dw,  Lambda(k) = sigma+(k)/(k.n) - 1,
//      G1(k) = min(1, (k.n)/sigma+(k)).
//    sigma+ is precomputed on a (theta_k, phi_k) node grid (default 1 deg x 2 deg: 91 x 180
//    nodes, theta_k in [0, 90] deg, phi_k periodic) and interpolated bilinearly. Each node is
//    a sum over "slope bins": the table's cells are gathered into at most sigma_bins x
//    sigma_bins bins (default 256 x 256, i.e. 4 x 4 cells of a 1025 table), each bin keeping
//    the moments of the interpolant, mass M = integral D dm_x dm_y and mean slope
//    (p, q) = integral D (m_x, m_y)/m_z dm_x dm_y / M (3 x 3 Gauss per cell inside r = 0.98;
//    rows integrated exactly in x near the rim, where 1/m_z is singular). Since
//    <k.m>+ / m_z = <k_z + k_x p + k_y q>+ is linear in the slope away from the horizon line of
//    k, the bin sum equals the integral of the interpolant exactly for every bin that line does
//    not cross (the error of the crossed bins grows with the bin size relative to the lobe:
//    max |G1 - Smith| 2e-5 for Beckmann alpha 0.3, 3e-4 for alpha 0.03 at 1025^2). The masses
//    are scaled so that sigma+(n) = 1 exactly (G1(n) = 1).
//  - Sampling: visible normals of a table would need a table per view direction; instead
//    sample_visible(v, ...) ignores v and draws m with density D(m)(m.n) per steradian
//    (NdfSampler, exact for the interpolant). sampling_pdf(v, m) returns that density, and
//    MicrofacetBrdf uses sampling_pdf, so its pdf and weights are exact (the weights are
//    F G2 (wi.m) / ((wi.n)(m.n)), larger variance at grazing than with visible normals).
//    pdf_visible(v, m) still gives the true visible-normal density D_v.

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "microbrdf/microfacet.hpp"
#include "microbrdf/ndf_io.hpp"
#include "microbrdf/tabulated_ndf.hpp"

namespace microbrdf {

struct TabulatedDistributionOptions {
  std::size_t sigma_bins = 256;  ///< slope bins per side for the sigma+ sums (<= resolution)
  std::size_t theta_steps = 90;  ///< sigma+ grid steps over theta_k in [0, 90] deg
  std::size_t phi_steps = 180;   ///< sigma+ grid steps over phi_k in [0, 360) deg
};

class TabulatedDistribution final : public MicrofacetDistribution {
 public:
  /// Takes the table (need not be normalised: D is divided by its disk integral). Throws
  /// InputError for a table with no positive mass inside the disk or non-finite values.
  explicit TabulatedDistribution(TabulatedNdf ndf, const TabulatedDistributionOptions& opt = {});
  TabulatedDistribution(const TabulatedDistribution&) = delete;
  TabulatedDistribution& operator=(const TabulatedDistribution&) = delete;

  double D(const Vec3& m) const override;
  /// sigma+(v)/(v.n) - 1 with sigma+ interpolated from the grid.
  double lambda(const Vec3& v) const override;
  /// NOT visible normals: m with density D(m)(m.n), whatever v (see the header comment).
  Vec3 sample_visible(const Vec3& v, double u1, double u2) const override;
  /// D(m)(m.n), the density of sample_visible.
  double sampling_pdf(const Vec3& v, const Vec3& m) const override;
  std::string describe() const override;

  /// sigma+(k) interpolated from the grid, for a unit k with k.z > 0.
  double sigma_plus(const Vec3& k) const;
  /// sigma+(k) summed over the slope bins directly (no grid interpolation; slow).
  double sigma_plus_direct(const Vec3& k) const;
  const TabulatedNdf& table() const { return *ndf_; }
  /// Z: the integral of the table's interpolant over the disk (D = eval / Z).
  double normalisation() const { return z_; }
  std::size_t sigma_bins() const { return bins_; }

 private:
  std::unique_ptr<TabulatedNdf> ndf_;  // heap: the sampler keeps a pointer to it
  std::unique_ptr<NdfSampler> sampler_;
  TabulatedDistributionOptions opt_;
  double z_ = 1, inv_z_ = 1;
  std::size_t bins_ = 0;
  std::vector<double> bm_, bp_, bq_;  // bin masses (sum 1) and mean slopes
  std::vector<double> sigma_;         // (theta_steps + 1) x phi_steps, row = theta
};

}  // namespace microbrdf
