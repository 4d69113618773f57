#pragma once
// Westin, Arvo & Torrance 1992: the real spherical-harmonic basis, the odd-completion basis that
// represents BRDFs (docs/theory.md §6) and the Monte Carlo estimator of the coefficient
// matrix. The BRDF built from the matrix is ShBrdf (sh_brdf.hpp). Directions are unit vectors in
// the local frame (n = +z).

#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "microbrdf/vec3.hpp"

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
  /// out[j] = sum_k weight[k] Y_j(w[k]) over n directions (w need not be unit; zero vectors
  /// count as the pole), four directions at a time (AVX2 where the CPU has it; the same bits
  /// either way). `out` holds size() values, overwritten. About 4x the rate of eval() per
  /// direction at lmax 15.
  void eval_sum(std::size_t n, const Vec3* w, const double* weight, double* out) const;
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
  // products wait in pend_u_/pend_v_ so that they are added as one rank-kPending update (a
  // register-tiled product on the calling thread, AVX2 where the CPU has it).
  mutable Eigen::MatrixXd sum_, pend_u_, pend_v_;
  mutable int n_pend_ = 0;
  static constexpr int kPending = 64;
  std::size_t n_incident_ = 0, n_rays_ = 0;
  double energy_sum_ = 0;
};

}  // namespace microbrdf
