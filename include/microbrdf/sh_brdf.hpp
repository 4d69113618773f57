#pragma once
// Westin, Arvo & Torrance 1992: BRDFs as matrices of real spherical-harmonic coefficients
// (docs/theory.md §6). Directions are unit vectors in the local frame of brdf.hpp (n = +z).
//
// Stored quantity: f(wi, wo) = rho(wi, wo) cos(theta_i) cos(theta_o), completed oddly in z in both
// arguments (W92 section 2.5), so only the basis functions with l + m odd survive (docs/theory.md
// §6.2). f(wi, wo) = Y(wi)^T M Y(wo) over that kept basis; M is symmetric (reciprocity by
// construction). The BRDF is grey (one matrix); a simulation at one wavelength says which in its
// metadata.

#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "microbrdf/brdf.hpp"
#include "microbrdf/sh_basis.hpp"

namespace microbrdf {

/// A synthetic "ray tracer" for validating the estimator without geometry: `n_incident`
/// directions U drawn cosine-weighted (p_U = cos/pi), and for each `rays` exits drawn with
/// brdf.sample(U) carrying R = weight (f cos / pdf). E[estimate] = the projection of `brdf`.
/// Deterministic for a seed. Used by tests and `microbrdf brdf sh-estimate`.
void sh_estimate_by_sampling(ShEstimator& e, const Brdf& brdf, std::size_t n_incident, int rays,
                             std::uint64_t seed, double wavelength_m);

/// Chunks of sh_estimate_chunked (fixed, so the result depends on the seed only).
constexpr std::size_t kShEstimateChunks = 16;
/// sh_estimate_by_sampling over min(16, n_incident) chunks of the incident directions, chunk c
/// seeded with seed * 1000003 + c, estimated in parallel (OpenMP) and merged in chunk order: the
/// result depends on the seed only, not on the thread count. `progress(done, chunks)` is called
/// as chunks finish (under a lock). Throws InputError for n_incident or rays < 1.
ShEstimator sh_estimate_chunked(const Brdf& brdf, int lmax, std::size_t n_incident, int rays,
                                std::uint64_t seed, double wavelength_m,
                                const std::function<void(std::size_t, std::size_t)>& progress = {});

class ShBrdf final : public Brdf {
 public:
  /// `m` is over the kept basis of lmax (symmetrised here: M = (m + m^T)/2). `meta` is carried
  /// into save() (scene, rays, seed, Q, wavelength...).
  ShBrdf(int lmax, const Eigen::MatrixXd& m, nlohmann::json meta = {});
  /// The symmetrised result of an estimator; meta gains incident_count, ray_count, q,
  /// mean_energy (unless already set).
  static ShBrdf from_estimator(const ShEstimator& e, nlohmann::json meta = {});
  /// Projection of any BRDF by product quadrature over both hemispheres (Gauss-Legendre in
  /// cos(theta) x midpoint rule in phi, n_theta x 2 n_theta nodes each; n_theta <= 0 picks
  /// lmax + 8): m_jk = 4 sum w_a w_b rho(a, b) cos_a cos_b Y_j(a) Y_k(b). For tests, comparisons
  /// with analytic models and `microbrdf brdf sh-project`.
  static ShBrdf project(const Brdf& brdf, int lmax, double wavelength_m, int n_theta = 0,
                        nlohmann::json meta = {});

  int lmax() const { return basis_.lmax(); }
  const ShOddBasis& basis() const { return basis_; }
  const Eigen::MatrixXd& matrix() const { return m_; }
  const nlohmann::json& meta() const { return meta_; }

  /// f = rho cos(theta_i) cos(theta_o) = Y(wi)^T M Y(wo), unclamped (may be slightly negative).
  double cosine_weighted(const Vec3& wi, const Vec3& wo) const;
  /// rho in 1/sr, clamped at 0; near the horizon the division by the cosines amplifies the
  /// truncation error (W92 section 5.1), so the cosines are clamped at `horizon_cos` (default
  /// 1e-3).
  double eval(const Vec3& wi, const Vec3& wo, double wavelength_m) const override;
  /// Importance sampling from a table of CDFs over outgoing cells (theta_o x phi_o), one per
  /// incident node (theta_i, and phi_i unless isotropic()), interpolated between nodes and mixed
  /// with a cosine lobe (10 %); pdf() is exactly the density drawn from. Where the expansion is
  /// <= 0 the sample comes back with weight 0. The table is built once on first use
  /// (std::call_once); sample()/pdf()/eval() are safe from many threads.
  std::optional<BrdfSample> sample(const Vec3& wi, double u1, double u2,
                                   double wavelength_m) const override;
  double pdf(const Vec3& wi, const Vec3& wo) const override;
  std::string describe() const override;

  /// One direction bound: c = M Y(w). A renderer with a fixed view direction per shading point
  /// (or a fixed light) binds it once; every other direction then costs one basis evaluation and
  /// a dot product instead of a matrix-vector product (~30x faster at lmax 30). By reciprocity
  /// it does not matter which of wi, wo is bound.
  struct Bound {
    Vec3 w;
    Eigen::VectorXd c;
  };
  Bound bind(const Vec3& w) const;
  /// rho(b.w, other) = eval(b.w, other) = eval(other, b.w), same clamping as eval().
  double eval_bound(const Bound& b, const Vec3& other) const;

  /// Directional albedo a(wi) = integral over the upper hemisphere of rho cos(theta_o) dwo, exact
  /// for the truncated expansion (hemisphere integrals of the basis).
  double albedo(const Vec3& wi) const;
  /// The same (the expansion is grey: the wavelength is ignored).
  double albedo(const Vec3& wi, double) const override { return albedo(wi); }
  /// The average of M over rotations about n (exact: 2 lmax + 1 equally spaced angles), i.e. the
  /// isotropic part of the BRDF; couplings between different |m| become exactly 0. For surfaces
  /// known to be isotropic this removes the anisotropic part of the Monte Carlo noise, and
  /// eval() then uses the block structure (~20x fewer operations at lmax 30).
  ShBrdf isotropic_average() const;
  /// True when every coefficient coupling different |m| is exactly 0 (eval uses the |m| blocks).
  bool block_diagonal_in_m() const { return !blocks_.empty(); }
  /// Gibbs attenuation (docs/theory.md §6.6): w(l) = 1 for l <= l_filter, exp(-(l - l_filter)^2 /
  /// (2 width^2)) above; m_jk <- w(l_j) w(l_k) m_jk.
  ShBrdf damped(int l_filter, double width) const;

  /// Binary file: magic "MBSHBRDF", uint32 JSON header length, JSON header (lmax, size, basis
  /// convention, meta), then size x size little-endian float64, row-major. Atomic write.
  void save(const std::string& path) const;
  /// Throws FileError naming the file on a short, corrupt or inconsistent file.
  static ShBrdf load(const std::string& path);
  /// The same from bytes in memory (`name` is used in error messages).
  static ShBrdf load_bytes(std::span<const std::uint8_t> bytes, const std::string& name);
  /// The file image save() writes.
  std::vector<std::uint8_t> to_bytes() const;

  /// True when M commutes with rotations about n (rho depends on phi_o - phi_i only), to a
  /// relative Frobenius tolerance of 2e-2 (so noisy estimates of isotropic surfaces qualify); the
  /// sampler then tabulates theta_i only. Only the sampler's efficiency depends on it.
  bool isotropic() const { return isotropic_; }

  void set_horizon_cos(double c) { horizon_cos_ = c; }

 private:
  ShOddBasis basis_;
  Eigen::MatrixXd m_;
  nlohmann::json meta_;
  double horizon_cos_ = 1e-3;
  bool isotropic_ = false;
  struct MBlock {  // kept functions with one |m|, and M restricted to them
    std::vector<int> idx;
    Eigen::MatrixXd m;
  };
  std::vector<MBlock> blocks_;  // empty unless M is exactly block diagonal in |m|
  struct SamplingTable;         // tabulated CDFs for sample()/pdf()
  struct LazyTable;             // built once on first use under std::call_once (thread-safe)
  std::shared_ptr<LazyTable> lazy_;
  const SamplingTable& table() const;
};

/// Directional albedo a(theta_i) of the expansion (exact) at azimuth 0 for theta_i = 0, 30, 45,
/// 60, 75 and 85 deg.
struct ShAlbedoPoint {
  double theta_i_deg = 0, albedo = 0;
};
std::vector<ShAlbedoPoint> sh_albedo_table(const ShBrdf& b);
/// Hemispherical albedo (1/pi) integral a(wi) cos(theta_i) dwi of the expansion (exact).
double sh_hemispherical_albedo(const ShBrdf& b);
/// Ringing of the truncated expansion: where is f = rho cos cos negative? On a grid of 9 x 8
/// incident (theta at cell centres of 10 deg, phi every 45 deg) and 18 x 36 outgoing (cell
/// centres of 5 x 10 deg) directions.
struct ShRinging {
  double negative_fraction = 0;  ///< of the 72 x 648 direction pairs
  double min_cosine_weighted = 0, max_cosine_weighted = 0;
};
ShRinging sh_ringing(const ShBrdf& b);

}  // namespace microbrdf
