#pragma once
// Multiple scattering between microfacets for any MicrofacetDistribution: the microfacet random
// walk of Heitz, Hanika, d'Eon, Dachsbacher 2016 ("Multiple-scattering microfacet BSDFs with
// the Smith model"), conductor case; theory and figures in docs/multiple_scattering.md.
//
// Local frame as everywhere (brdf.hpp): n = +z, wi and wo point away from the surface, f in 1/sr,
// wavelengths in metres. The walk uses only what every distribution provides: its own Smith
// Lambda(v) (extended below the horizon by Lambda(-v) = -1 - Lambda(v)) and its own
// sample_visible / sampling_pdf. Heights are uncorrelated with slopes and uniform on [-1, 1]
// (Heitz shows the BRDF does not depend on the height distribution; the uniform one has the
// simplest inverse CDF). A ray travelling down from height h0 meets the microsurface at h with
// C1(h) = C1(h0) U^(1/(1 + Lambda)); a ray travelling up escapes with probability
// G1 = C1(h0)^Lambda(w). At each hit a normal m is drawn from the visible normals of the
// reversed ray and the ray is mirrored about m, its weight multiplied by F(cos, lambda).
// Upward rays (view below the horizon) draw m from the visible normals of the direction
// mirrored to the upper side and keep it with probability <v.m>+ / <v'.m>+ (<= 1), which is
// exact for every distribution whose sample_visible is exact. For a tabulated NDF, whose
// sampler is only close to the visible normals, the walk weights each normal by
// pdf_visible / sampling_pdf (unbiased for downward rays).
//
// Order 1 of the walk is the single-scattering microfacet BRDF with the height-correlated Smith
// G2 exactly (MicrofacetBrdf); the classes below add orders 2 and more to it.
//
// Everything random is counter-based (SplitMix64 streams seeded from the arguments and a
// fixed seed), so every result is the same whatever the thread count or call order.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "microbrdf/brdf.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/microfacet.hpp"
#include "microbrdf/microfacet_brdf.hpp"

namespace microbrdf {

/// A small counter-based random stream (SplitMix64) for the walk; doubles in [0, 1).
class WalkRng {
 public:
  explicit WalkRng(std::uint64_t seed) : state_(seed) {}
  double next();

 private:
  std::uint64_t state_;
};

/// The microfacet random walk on one distribution (conductor: every hit reflects).
class MicrofacetRandomWalk {
 public:
  /// `max_order`: a walk still on the surface after this many hits is dropped (its energy is
  /// below 1e-6 of the total for alpha <= 1; docs/multiple_scattering.md).
  explicit MicrofacetRandomWalk(std::shared_ptr<const MicrofacetDistribution> d,
                                int max_order = 100);

  /// One walk from the light direction wi (wi.z > 0) until it leaves the surface.
  struct Exit {
    Vec3 wo;               ///< the direction it leaves in (wo.z > 0)
    double weight = 0;     ///< the product of F over the hits (times the tabulated-NDF weights)
    int order = 0;         ///< number of hits (>= 1)
    double weight_f1 = 0;  ///< the same walk's weight with F = 1 (only the tabulated weights)
  };
  /// `fresnel` may be null (F = 1). The first normal comes from (u1, u2), the rest from `rng`.
  /// Nothing when the walk was dropped (max_order) or the first hit could not be sampled.
  std::optional<Exit> sample(const Vec3& wi, double u1, double u2, WalkRng& rng,
                             const Fresnel* fresnel, double wavelength_m) const;

  /// One walk with next-event estimation towards wo: an unbiased estimate of
  /// f(wi, wo) cos(theta_o) (dimensionless per steradian, i.e. 1/sr) of the orders
  /// [min_order, max_order].
  double eval_cos(const Vec3& wi, const Vec3& wo, WalkRng& rng, const Fresnel* fresnel,
                  double wavelength_m, int min_order = 2) const;

  /// eval_cos_many for one wo (walk Lambda lambda_o) at n wavelengths at once: the walk (heights,
  /// normals) does not depend on the wavelength, only its Fresnel factors do. Adds to out[k]
  /// exactly what eval_cos_many would at wavelengths_m[k] from the same stream.
  void eval_cos_spectral(const Vec3& wi, const Vec3& wo, double lambda_o, WalkRng& rng,
                         const Fresnel* fresnel, const double* wavelengths_m, int n, double* out,
                         int min_order = 2) const;

  /// Next-event estimation of one walk towards n directions at once (the table builder): adds
  /// each estimate of f cos(theta_o) of orders >= min_order to out[j] for wos[j], whose walk
  /// Lambda is lambda_o[j] (= lambda(wos[j])). `energy`, when given, gets the estimate of the
  /// energy of those orders (the weight after each hit times its escape probability).
  void eval_cos_many(const Vec3& wi, const Vec3* wos, const double* lambda_o, std::size_t n,
                     WalkRng& rng, const Fresnel* fresnel, double wavelength_m, double* out,
                     int min_order = 2, double* energy = nullptr) const;

  /// The walk's Smith Lambda for any direction (Lambda(-v) = -1 - Lambda(v) below the
  /// horizon; clamped to >= 0 above it).
  double lambda(const Vec3& v) const;
  const MicrofacetDistribution& distribution() const { return *d_; }
  int max_order() const { return max_order_; }

 private:
  bool next_height(const Vec3& wr, double& c1, WalkRng& rng) const;
  bool sample_normal(const Vec3& wr, double u1, double u2, WalkRng& rng, Vec3& m, double& w) const;
  double sigma(const Vec3& v) const;
  double phase(const Vec3& v, const Vec3& wo, const Fresnel* fresnel, double wavelength_m,
               double sigma_v) const;
  std::shared_ptr<const MicrofacetDistribution> d_;
  int max_order_;
  bool weighted_ = false;  // a tabulated NDF: weight normals by pdf_visible / sampling_pdf
};

/// Grid and effort of the multiple-scattering table (tabulate_multiple_scattering).
struct MsTableOptions {
  std::size_t theta_nodes = 12;  ///< nodes in theta at (k + 1/2) 90 deg / theta_nodes
  std::size_t phi_nodes = 24;    ///< nodes in phi at k 360 deg / phi_nodes
  std::size_t walks = 256;       ///< walks per incidence node (next-event estimation to all nodes)
  std::size_t energy_walks = 4096;  ///< walks per incidence node for its energy (no estimation
                                    ///< towards the nodes: cheap)
  std::uint64_t seed = 1;           ///< the walks of node i use stream chunk_seed(seed, i)
  int threads = 0;                  ///< OpenMP threads (0: all); no effect on the result
};

/// The deterministic tabulated form: the orders >= 2 of f(wi, wo) on a node grid of both
/// directions, and the energy they carry per incidence. Built with a fixed seed per
/// incidence node, so it does not depend on the thread count. eval interpolates bilinearly in
/// (theta, phi) of both directions (theta clamped to the outermost nodes); each incidence row
/// is scaled so that the integral of its interpolant over wo equals its energy (the walks'
/// estimate, exact per walk), which corrects the interpolant's loss near the horizon.
class MsTable {
 public:
  MsTable() = default;
  /// f_ms(wi, wo) in 1/sr, interpolated.
  double eval(const Vec3& wi, const Vec3& wo) const;
  /// The energy of orders >= 2 at incidence wi: integral f_ms cos(theta_o) dwo, interpolated in
  /// theta_i, phi_i from the node sums (dimensionless).
  double energy(const Vec3& wi) const;
  /// Node values: f_ms at incidence node i and outgoing node j (1/sr).
  double node(std::size_t i, std::size_t j) const { return f_[i * nodes() + j]; }
  /// Energy at incidence node i: the mean over energy_walks walks of the weight after each hit
  /// (>= 2) times its escape probability; not the quadrature of the node values.
  double node_energy(std::size_t i) const { return e_[i]; }
  /// Direction of node k (k = it * phi_nodes + ip).
  Vec3 direction(std::size_t k) const;
  std::size_t nodes() const { return nt_ * np_; }
  std::size_t theta_nodes() const { return nt_; }
  std::size_t phi_nodes() const { return np_; }
  /// Bytes of the node values.
  std::size_t memory_bytes() const { return (f_.size() + e_.size()) * sizeof(double); }

 private:
  friend MsTable tabulate_multiple_scattering(const MicrofacetRandomWalk&, const Fresnel*, double,
                                              const MsTableOptions&);
  template <class Get>
  double interp(const Vec3& v, Get get) const;
  void fill_rotations();
  void normalise_rows();
  std::size_t nt_ = 0, np_ = 0;
  std::vector<double> f_, e_;
};

/// Tabulates orders >= 2 of the walk (fresnel null: F = 1). Checks the memory budget first.
MsTable tabulate_multiple_scattering(const MicrofacetRandomWalk& walk, const Fresnel* fresnel,
                                     double wavelength_m, const MsTableOptions& opt = {});

/// Options of the multiple-scattering BRDF.
struct MultipleScatteringOptions {
  int eval_walks = 16;     ///< walks per eval() (the stochastic estimate of orders >= 2)
  int max_order = 100;     ///< hits after which a walk is dropped
  std::uint64_t seed = 1;  ///< fixed seed of every stream
  MsTableOptions table;    ///< the F = 1 table behind pdf()
};

/// Single plus multiple scattering for any distribution (conductor), a Brdf for the renderer,
/// `brdf slice`, export and reports:
///  - eval(wi, wo) = the single-scattering BRDF (MicrofacetBrdf, height-correlated G2) exactly
///    + the mean of eval_walks next-event estimates of orders >= 2 with the material's Fresnel
///    term. The walks are seeded from the bits of (wi, wo) and the seed, not the wavelength:
///    repeated calls give the same number, and a spectrum is smooth in lambda. Its relative
///    standard error falls as 1/sqrt(eval_walks) (docs/multiple_scattering.md).
///  - sample(wi, u1, u2) draws wo from a mixture whose density pdf() gives exactly: with
///    probability c(wi) a cosine lobe (for orders >= 2, which are broad), else the
///    single-scattering lobe (visible normals of wi, reflected); weight = eval cos / pdf.
///    c(wi) = the F = 1 energy of orders >= 2 (the MsTable built in the constructor), clamped
///    to [0.02, 0.9]. (A walk's exit direction has no closed-form density, and the renderer
///    weights every wavelength by eval / pdf, so sample() does not return walk exits;
///    MicrofacetRandomWalk::sample does.)
///  - pdf(wi, wo) = (1 - c) MicrofacetBrdf::pdf + c cos(theta_o) / pi.
class MultipleScatteringBrdf final : public Brdf {
 public:
  MultipleScatteringBrdf(std::shared_ptr<const MicrofacetDistribution> d,
                         std::shared_ptr<const Fresnel> f,
                         const MultipleScatteringOptions& opt = {});
  double eval(const Vec3& wi, const Vec3& wo, double wavelength_m) const override;
  /// The same walks as eval() at every wavelength (they do not depend on it), taken once with
  /// each wavelength's Fresnel factors: f[k] == eval(wi, wo, wavelengths_m[k]) bit for bit.
  void eval_spectral(const Vec3& wi, const Vec3& wo, const double* wavelengths_m, int n,
                     double* f) const override;
  std::optional<BrdfSample> sample(const Vec3& wi, double u1, double u2,
                                   double wavelength_m) const override;
  double pdf(const Vec3& wi, const Vec3& wo) const override;
  std::string describe() const override;

  /// The single-scattering part alone (MicrofacetBrdf::eval).
  double eval_single(const Vec3& wi, const Vec3& wo, double wavelength_m) const;
  /// The multiple-scattering part alone, with `walks` walks (the eval() estimate for
  /// walks = eval_walks).
  double eval_multiple(const Vec3& wi, const Vec3& wo, double wavelength_m, int walks) const;
  /// The energy of orders >= 2 with F = 1 at incidence wi (the table; the energy single
  /// scattering loses on a white surface).
  double energy_lost_single(const Vec3& wi) const { return table_.energy(wi); }
  const MicrofacetRandomWalk& walk() const { return walk_; }
  const MsTable& table() const { return table_; }
  const MicrofacetBrdf& single() const { return single_; }

 private:
  double cosine_share(const Vec3& wi) const;
  MicrofacetBrdf single_;
  std::shared_ptr<const Fresnel> f_;
  MicrofacetRandomWalk walk_;
  MultipleScatteringOptions opt_;
  MsTable table_;
};

}  // namespace microbrdf
