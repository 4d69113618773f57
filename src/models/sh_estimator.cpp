// The Monte Carlo estimator of the SH coefficient matrix (W92 eqs. 17 and 25, constants of
// docs/theory.md §6.4) and the convergence measure Q (eqs. 26-27 with 1/J^2, docs/theory.md §6.5).
#include <omp.h>

#include <cmath>
#include <string>

#include "microbrdf/error.hpp"
#include "microbrdf/sh_basis.hpp"

namespace microbrdf {
namespace {
constexpr double kPi = 3.14159265358979323846;
}

ShEstimator::ShEstimator(int lmax) : basis_(lmax) {
  sum_ = Eigen::MatrixXd::Zero(basis_.size(), basis_.size());
  pend_u_.resize(basis_.size(), kPending);
  pend_v_.resize(basis_.size(), kPending);
}

void ShEstimator::flush() const {
  if (n_pend_ == 0) return;
  // An estimator is one thread's accumulator (the tracers run one per worker thread): the
  // product stays on the calling thread. Eigen would otherwise open an OpenMP team of
  // omp_get_max_threads() inside every worker (nested parallelism: with one worker, a second
  // spinning thread for a product of a few microseconds). Eigen reads the thread count per call
  // from this thread's OpenMP setting, so it is lowered for the product only.
  const int saved = omp_get_max_threads();
  if (saved > 1) omp_set_num_threads(1);
  sum_.noalias() += pend_u_.leftCols(n_pend_) * pend_v_.leftCols(n_pend_).transpose();
  if (saved > 1) omp_set_num_threads(saved);
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
