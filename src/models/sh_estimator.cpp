// The Monte Carlo estimator of the SH coefficient matrix (W92 eqs. 17 and 25, constants of
// docs/theory.md §6.4) and the convergence measure Q (eqs. 26-27 with 1/J^2, docs/theory.md §6.5).
#include <cmath>
#include <cstddef>
#include <cstring>
#include <string>

#include "core/simd_clones.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/sh_basis.hpp"

namespace microbrdf {
namespace {
constexpr double kPi = 3.14159265358979323846;

// Four lanes of doubles (GCC/Clang vector extension: one AVX2 register, two SSE2 ones).
typedef double V4 __attribute__((vector_size(32)));

// c += a b^T for column-major a, b (n x k, leading dimension n) and c (n x n): the estimator's
// batched outer products, on the calling thread (an estimator is one worker's accumulator; no
// library threads inside). Tiles of 8 rows x 4 columns held in registers over the k products.
MICROBRDF_SIMD_CLONES
void rank_update(int n, int k, const double* a, const double* b, double* c) {
  const int n8 = n - n % 8, n4 = n - n % 4;
  for (int j = 0; j < n4; j += 4) {
    for (int i = 0; i < n8; i += 8) {
      V4 s[2][4] = {};
      for (int q = 0; q < k; ++q) {
        const double* aq = a + std::ptrdiff_t(q) * n + i;
        const double* bq = b + std::ptrdiff_t(q) * n + j;
        V4 a0, a1;
        std::memcpy(&a0, aq, sizeof a0);
        std::memcpy(&a1, aq + 4, sizeof a1);
        for (int t = 0; t < 4; ++t) {
          s[0][t] += a0 * bq[t];
          s[1][t] += a1 * bq[t];
        }
      }
      for (int t = 0; t < 4; ++t) {
        double* ct = c + std::ptrdiff_t(j + t) * n + i;
        V4 c0, c1;
        std::memcpy(&c0, ct, sizeof c0);
        std::memcpy(&c1, ct + 4, sizeof c1);
        c0 += s[0][t];
        c1 += s[1][t];
        std::memcpy(ct, &c0, sizeof c0);
        std::memcpy(ct + 4, &c1, sizeof c1);
      }
    }
    for (int i = n8; i < n; ++i)
      for (int t = 0; t < 4; ++t) {
        double s = 0;
        for (int q = 0; q < k; ++q)
          s += a[std::ptrdiff_t(q) * n + i] * b[std::ptrdiff_t(q) * n + j + t];
        c[std::ptrdiff_t(j + t) * n + i] += s;
      }
  }
  for (int j = n4; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      double s = 0;
      for (int q = 0; q < k; ++q) s += a[std::ptrdiff_t(q) * n + i] * b[std::ptrdiff_t(q) * n + j];
      c[std::ptrdiff_t(j) * n + i] += s;
    }
}

}  // namespace

ShEstimator::ShEstimator(int lmax) : basis_(lmax) {
  sum_ = Eigen::MatrixXd::Zero(basis_.size(), basis_.size());
  pend_u_.resize(basis_.size(), kPending);
  pend_v_.resize(basis_.size(), kPending);
}

void ShEstimator::flush() const {
  if (n_pend_ == 0) return;
  rank_update(basis_.size(), n_pend_, pend_u_.data(), pend_v_.data(), sum_.data());
  n_pend_ = 0;
}

void ShEstimator::add_incident(const Vec3& u, double pdf_u, const double* exit_sum,
                               std::size_t rays, double energy) {
  if (!(pdf_u > 0) || !std::isfinite(pdf_u))
    throw InputError("ShEstimator: incident density must be positive and finite, got " +
                     std::to_string(pdf_u));
  if (rays == 0) throw InputError("ShEstimator: an incident direction needs at least one ray");
  ++n_incident_;
  n_rays_ += rays;
  const double cos_u = u.z() / u.norm();
  if (!(cos_u > 0)) return;  // a direction below the horizon contributes nothing (counts in N)
  // m~ = (1/N) sum_U [cos/p] 4 Y(U) (sum_exits R Y(V)) / rays  (docs/theory.md §6.4: the 4 is the
  // odd completion in both arguments, cos/p the measure of the incident directions).
  const double w = 4 * cos_u / pdf_u / static_cast<double>(rays);
  const int n = basis_.size();
  basis_.eval(u, pend_u_.col(n_pend_).data());
  pend_u_.col(n_pend_) *= w;
  pend_v_.col(n_pend_) = Eigen::Map<const Eigen::VectorXd>(exit_sum, n);
  if (++n_pend_ == kPending) flush();
  // Hemispherical-average albedo: (1/pi) int a(U) cos dU, a(U) = energy / rays.
  energy_sum_ += cos_u / (kPi * pdf_u) * energy / static_cast<double>(rays);
}

void ShEstimator::merge(const ShEstimator& other) {
  if (other.basis_.lmax() != basis_.lmax())
    throw InputError("ShEstimator::merge: lmax " + std::to_string(other.basis_.lmax()) +
                     " differs from " + std::to_string(basis_.lmax()));
  flush();
  other.flush();
  sum_ += other.sum_;
  n_incident_ += other.n_incident_;
  n_rays_ += other.n_rays_;
  energy_sum_ += other.energy_sum_;
}

std::vector<double> ShEstimator::pack() const {
  flush();
  std::vector<double> v(sum_.data(), sum_.data() + sum_.size());
  // Counts below 2^53 travel exactly as doubles.
  v.push_back(static_cast<double>(n_incident_));
  v.push_back(static_cast<double>(n_rays_));
  v.push_back(energy_sum_);
  return v;
}

void ShEstimator::merge_packed(const std::vector<double>& state) {
  const auto j = static_cast<std::size_t>(basis_.size());
  if (state.size() != j * j + 3)
    throw InputError("ShEstimator::merge_packed: " + std::to_string(state.size()) +
                     " numbers for a " + std::to_string(j) + " x " + std::to_string(j) + " matrix");
  flush();
  sum_ += Eigen::Map<const Eigen::MatrixXd>(state.data(), basis_.size(), basis_.size());
  n_incident_ += static_cast<std::size_t>(state[j * j]);
  n_rays_ += static_cast<std::size_t>(state[j * j + 1]);
  energy_sum_ += state[j * j + 2];
}

Eigen::MatrixXd ShEstimator::raw() const {
  if (n_incident_ == 0) return Eigen::MatrixXd::Zero(basis_.size(), basis_.size());
  flush();
  return sum_ / static_cast<double>(n_incident_);
}

double ShEstimator::q() const {
  const Eigen::MatrixXd r = raw();
  const double j = basis_.size();
  return (r - r.transpose()).cwiseAbs().sum() / (j * j);
}

double ShEstimator::mean_energy() const {
  return n_incident_ == 0 ? 0.0 : energy_sum_ / static_cast<double>(n_incident_);
}

}  // namespace microbrdf
