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
#include <memory>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "microbrdf/brdf.hpp"

namespace microbrdf {

/// Largest lmax the evaluators accept (recurrence tables are precomputed up to it).
constexpr int kShMaxL = 128;
/// Index of Y_lm in the full real basis, k = l^2 + l + m (-l <= m <= l).
constexpr int sh_index(int l, int m) { return l * l + l + m; }
/// Number of functions in the full basis up to lmax: (lmax + 1)^2.
constexpr int sh_count(int lmax) { return (lmax + 1) * (lmax + 1); }
/// All real spherical harmonics Y_k(w), k < sh_count(lmax), orthonormal on the sphere, by the
/// normalised recurrence (stable to lmax >= 40). `out` must hold sh_count(lmax) values.
/// Convention: Y_l0 = Kbar P_l, Y_lm = sqrt2 Kbar P_l^|m| cos(m phi) (m > 0), sin(|m| phi) (m < 0),
/// without the Condon-Shortley phase; phi = atan2(w_y, w_x) (0 at the pole); w need not be unit.
/// Throws InputError for lmax outside [0, kShMaxL].
void sh_eval(int lmax, const Vec3& w, double* out);
/// Position of (l, m), l + m odd, in the kept basis: l (l - 1) / 2 + (m + l - 1) / 2.
constexpr int sh_odd_index(int l, int m) { return l * (l - 1) / 2 + (m + l - 1) / 2; }

/// The basis kept after the odd completion: the (l, m) with l + m odd, l <= lmax, in increasing k.
class ShOddBasis {
 public:
  /// Throws InputError for lmax outside [1, kShMaxL].
  explicit ShOddBasis(int lmax);
  int lmax() const { return lmax_; }
  int size() const { return static_cast<int>(l_.size()); }  ///< lmax (lmax + 1) / 2
  int l(int j) const { return l_[j]; }
  int m(int j) const { return m_[j]; }
  /// Y_j(w) for the kept functions; `out` holds size() values. Cost O(lmax^2).
  void eval(const Vec3& w, double* out) const;
  /// Integral of Y_j over the upper hemisphere (for albedos); 0 unless m = 0.
  const std::vector<double>& hemisphere_integrals() const { return hemi_; }

 private:
  int lmax_;
  std::vector<int> l_, m_;
  std::vector<double> hemi_;
};

/// The Monte Carlo estimator of W92 eq. 17 / 25 with the constants of docs/theory.md §6.4:
///   m~_jk = (1/N) sum_n [cos(theta_U) / p_U(U)] * 4 * Y_j(U_n) sum_exits R Y_k(V) / (rays per U)
/// Callers trace rays for one incident direction U at a time, sum R * Y(V) over all exits of all
/// the rays started for U (N_p target points x N_b branches), and hand over that sum.
/// Memory is O(size^2), independent of the number of rays. Not thread-safe: one per thread, merge.
class ShEstimator {
 public:
  explicit ShEstimator(int lmax);
  const ShOddBasis& basis() const { return basis_; }
  /// One incident direction `u` (upper hemisphere) drawn with density `pdf_u` per steradian,
  /// `exit_sum[k]` = sum over exits of R * Y_k(V) (kept basis), `rays` = rays started for u
  /// (every ray counts, including absorbed ones), `energy` = sum of exit R (for the albedo check).
  /// A `u` at or below the horizon counts in N and adds nothing. Throws InputError for
  /// pdf_u <= 0 or rays = 0.
  void add_incident(const Vec3& u, double pdf_u, const double* exit_sum, std::size_t rays,
                    double energy);
  void merge(const ShEstimator& other);
  /// The estimator's whole state as numbers (the J x J sum, column-major, then N, rays and the
  /// energy sum), exact, for sending between processes; merge_packed folds such a state in,
  /// exactly as merge() would. Throws InputError when the size does not match lmax.
  std::vector<double> pack() const;
  void merge_packed(const std::vector<double>& state);
  std::size_t incident_count() const { return n_incident_; }
  std::size_t ray_count() const { return n_rays_; }
  /// The unsymmetrised estimate M~ (kept basis, size() x size()).
  Eigen::MatrixXd raw() const;
  /// W92 eqs. 26-27 with the J^2 normalisation of docs/theory.md §6.5: Q = sum |M~ - M~^T| / J^2.
  double q() const;
  /// Mean exit energy per ray, averaged with weight cos(theta_U)/(pi p_U): the estimate of the
  /// hemispherical albedo (1/pi) integral a(U) cos(theta_U) dU; diagnostics only.
  double mean_energy() const;

 private:
  void flush() const;  // folds the pending batch into sum_ (one matrix product)
  ShOddBasis basis_;
  // sum over incident directions of w(U) Y(U) exit_sum^T / rays; the last < kPending outer
  // products wait in pend_u_/pend_v_ so that they are added as one GEMM (2.5x faster than
  // rank-1 updates at lmax 30).
  mutable Eigen::MatrixXd sum_, pend_u_, pend_v_;
  mutable int n_pend_ = 0;
  static constexpr int kPending = 32;
  std::size_t n_incident_ = 0, n_rays_ = 0;
  double energy_sum_ = 0;
};

/// A synthetic "ray tracer" for validating the estimator without geometry: `n_incident`
/// directions U drawn cosine-weighted (p_U = cos/pi), and for each `rays` exits drawn with
/// brdf.sample(U) carrying R = weight (f cos / pdf). E[estimate] = the projection of `brdf`.
/// Deterministic for a seed. Used by tests and `microbrdf brdf sh-estimate`.
void sh_estimate_by_sampling(ShEstimator& e, const Brdf& brdf, std::size_t n_incident, int rays,
                             std::uint64_t seed, double wavelength_m);

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

}  // namespace microbrdf
