#pragma once
// A TabulatedNdf used as a microfacet distribution (docs/theory.md §2.3 and 2.4).
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
//  - Sampling (TabulatedSampling::Visible, the default): approximately the visible normals
//    D_v(m) = G1(v) <v.m>+ D(m) / (v.n), with an exact pdf. Two levels over the table's cells:
//    coarse cells C (default 128 x 128 blocks) drawn with probability
//      P(C | v) = (1 - eps) sum_k w_k(v) P_k(C) + eps M_C / Z,
//    where P_k(C) = integral_C D <v_k.m>+ dw / sigma+(v_k) are visible-normal tables for view
//    nodes v_k on a (theta, phi) grid (default 5 deg x 15 deg: 19 x 24 tables),
//    w_k(v) bilinear weights of the four nodes around v, M_C the interpolant's mass in C and
//    eps (default 0.05) a defensive share of the plain D(m)(m.n) probabilities (positive pdf
//    wherever D > 0, weights at most 1/eps times the plain sampler's); then a cell inside C
//    with probability m_f / M_C and the bilinear density inside it exactly. So
//      sampling_pdf(v, m) = P(C(m) | v) eval(m) / M_C(m) * m_z     (per steradian)
//    is exactly the density sample_visible draws from. Within a coarse cell the density is
//    D(m)(m.n) (the factor <v.m>+ / m_z is replaced by its mean over the cell), so the weights
//    of MicrofacetBrdf, F G2 D (wi.m) / ((wi.n) q), are close to F G2 / G1(wi). The view
//    tables hold float CDFs (the pdf uses the same float differences, so it stays exact) over
//    each row's span of coarse cells with mass: 34 MB in all for a 1025^2 Beckmann table, 22 MB
//    for a 513^2 measured NDF covering part of the disk (docs/benchmarks.md).
//  - TabulatedSampling::Ndf (the former sampler, kept for comparison): sample_visible ignores v
//    and draws m with density D(m)(m.n) (NdfSampler); the weights are F G2 (wi.m) /
//    ((wi.n)(m.n)), with a much larger variance at grazing wi.
//    pdf_visible(v, m) gives the true visible-normal density D_v in both cases.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "microbrdf/microfacet.hpp"
#include "microbrdf/ndf_sampler.hpp"
#include "microbrdf/tabulated_ndf.hpp"

namespace microbrdf {

namespace detail {
class VisibleNormalTables;
}

/// What the visible-normal sampler and its density share for one viewer direction v: the four
/// view tables around v and their weights (TabulatedDistribution::view_mix). A path tracer
/// computes it once per shading point; the calls that take it give the same numbers as
/// sample_visible(v, ...) and sampling_pdf(v, ...).
struct TabulatedViewMix {
  std::size_t table[4] = {0, 0, 0, 0};
  double w[4] = {0, 0, 0, 0};  ///< (1 - eps) w_k; the defensive Q has weight eps
};

/// One look-up of the table at a microfacet normal m (TabulatedDistribution::lookup): the
/// interpolant's value and the cell it came from, shared by D(m) and sampling_pdf(v, m).
struct TabulatedLookup {
  double e = 0;        ///< TabulatedNdf::eval(m) (D(m) = e / Z)
  double mz = 0;       ///< m_z / |m|
  std::size_t cx = 0;  ///< the cell of the bilinear interpolation (valid when e != 0)
  std::size_t cy = 0;
};

/// How sample_visible draws microfacet normals (see the header comment).
enum class TabulatedSampling {
  Visible,  ///< approximate visible normals of v, exact pdf (default)
  Ndf,      ///< D(m)(m.n) whatever v (the plain table sampler)
};
/// "visible" | "ndf"; InputError otherwise.
TabulatedSampling parse_tabulated_sampling(const std::string& name);
std::string to_string(TabulatedSampling s);

struct TabulatedDistributionOptions {
  std::size_t sigma_bins = 256;  ///< slope bins per side for the sigma+ sums (<= resolution)
  std::size_t theta_steps = 90;  ///< sigma+ grid steps over theta_k in [0, 90] deg
  std::size_t phi_steps = 180;   ///< sigma+ grid steps over phi_k in [0, 360) deg
  TabulatedSampling sampling = TabulatedSampling::Visible;
  std::size_t vn_coarse = 128;      ///< visible sampling: coarse cells per side (<= cells)
  std::size_t vn_theta_steps = 18;  ///< view-node steps over theta_v in [0, 90] deg
  std::size_t vn_phi_steps = 24;    ///< view-node steps over phi_v in [0, 360) deg
  double vn_defensive = 0.05;       ///< share eps of the plain D(m)(m.n) probabilities, (0, 1]
};

class TabulatedDistribution final : public MicrofacetDistribution {
 public:
  /// Takes the table (need not be normalised: D is divided by its disk integral). Throws
  /// InputError for a table with no positive mass inside the disk or non-finite values.
  explicit TabulatedDistribution(TabulatedNdf ndf, const TabulatedDistributionOptions& opt = {});
  ~TabulatedDistribution() override;
  TabulatedDistribution(const TabulatedDistribution&) = delete;
  TabulatedDistribution& operator=(const TabulatedDistribution&) = delete;

  double D(const Vec3& m) const override;
  /// sigma+(v)/(v.n) - 1 with sigma+ interpolated from the grid.
  double lambda(const Vec3& v) const override;
  /// Approximate visible normals of v (sampling visible) or D(m)(m.n) whatever v (ndf); see
  /// the header comment. Thread-safe (all tables are built in the constructor).
  Vec3 sample_visible(const Vec3& v, double u1, double u2) const override;
  /// Exactly the density per steradian of sample_visible(v, ...).
  double sampling_pdf(const Vec3& v, const Vec3& m) const override;
  bool samples_visible_exactly() const override { return false; }
  std::string describe() const override;

  /// The hot paths of a renderer, split so that one viewer direction and one table look-up
  /// serve several calls; each gives exactly (bit for bit) the number of the call it stands for.
  /// The view tables' weights for v (any v; for sampling ndf, zeros).
  TabulatedViewMix view_mix(const Vec3& v) const;
  /// = sample_visible(v, u1, u2) for x = view_mix(v).
  Vec3 sample_visible(const TabulatedViewMix& x, const Vec3& v, double u1, double u2) const;
  /// = D(m); fills q for sampling_pdf(x, m, q).
  double lookup(const Vec3& m, TabulatedLookup& q) const;
  /// Hints the memory sampling_pdf(x, m, q) will read (no effect on any result).
  void prefetch_pdf(const TabulatedViewMix& x, const TabulatedLookup& q) const;
  /// = sampling_pdf(v, m) for x = view_mix(v) and q from lookup(m, q).
  double sampling_pdf(const TabulatedViewMix& x, const Vec3& m, const TabulatedLookup& q) const;

  /// sigma+(k) interpolated from the grid, for a unit k with k.z > 0.
  double sigma_plus(const Vec3& k) const;
  /// sigma+(k) summed over the slope bins directly (no grid interpolation; slow).
  double sigma_plus_direct(const Vec3& k) const;
  const TabulatedNdf& table() const { return *ndf_; }
  /// Z: the integral of the table's interpolant over the disk (D = eval / Z).
  double normalisation() const { return z_; }
  std::size_t sigma_bins() const { return bins_; }
  TabulatedSampling sampling() const { return opt_.sampling; }
  /// Bytes held by the visible-normal tables (0 for sampling ndf).
  std::size_t sampling_memory_bytes() const;

 private:
  std::unique_ptr<TabulatedNdf> ndf_;  // heap: the sampler keeps a pointer to it
  std::unique_ptr<NdfSampler> sampler_;
  std::unique_ptr<detail::VisibleNormalTables> vn_;  // sampling visible only
  TabulatedDistributionOptions opt_;
  double z_ = 1, inv_z_ = 1;
  std::size_t bins_ = 0;
  std::vector<double> bm_, bp_, bq_;  // bin masses (sum 1) and mean slopes
  std::vector<double> sigma_;         // (theta_steps + 1) x phi_steps, row = theta
  // TabulatedNdf::eval_disk's constants (the same expressions, so the same numbers) and one bit
  // per cell: set where a corner is not +0 (cells of +0 corners interpolate to +0 without
  // reading the table).
  const double* d_ = nullptr;
  std::size_t n_ = 0;
  double inv_h_ = 1, x0_ = -1, y0_ = -1, last_ = 0, top_ = 0;
  bool full_ = true;
  std::vector<std::uint64_t> live_;  // cells x words_ words, row-major by cell row
  std::size_t words_ = 0;
};

}  // namespace microbrdf
