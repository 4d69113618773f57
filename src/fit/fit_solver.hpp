#pragma once
// The fit's solvers on the objective of fit_context.hpp. Private to src/fit/.
#include <functional>
#include <string>
#include <vector>

#include "fit/fit_context.hpp"

namespace microbrdf::fit_detail {

struct LmResult {
  int iterations = 0;
  bool converged = false;
  std::string message;
  double cost = 0, initial_cost = 0;
};

/// Levenberg-Marquardt on normal_equations() with box bounds by projection (stopping rules:
/// relative cost change 1e-13, gradient 1e-14, relative step 1e-11). x: the k shape parameters
/// then log amplitude (held fixed when !amp_free); lo, hi: bounds of the same k + 1 entries.
LmResult levenberg_marquardt(const FitContext& c, double* x, bool amp_free, const double* lo,
                             const double* hi, int max_iterations);

/// Nelder-Mead (reference solver; the caller clamps to bounds in f). Returns the iterations.
int nelder_mead(const std::function<double(const std::vector<double>&)>& f, std::vector<double>& x,
                const std::vector<double>& step, int max_evals, double& fbest, bool& converged);

/// Ceres' Levenberg-Marquardt on the same residuals with the models' automatic derivatives
/// (reference solver); bounds as for levenberg_marquardt (infinite: none).
LmResult ceres_solve(const FitContext& c, double* shape, double* log_amp, const double* lo,
                     const double* hi, int max_iterations, int threads);

}  // namespace microbrdf::fit_detail
