#pragma once
// The fit's objective (docs/fitting.md): the region of interest of a table, its transformed
// values g(T), the forward operator (node values or tent-cell averages of the model) and the
// residuals' cost and normal equations for any registered model (ndf_model.hpp). Private to
// src/fit/.
#include <cmath>
#include <cstddef>
#include <memory>
#include <vector>

#include "microbrdf/fit.hpp"
#include "microbrdf/ndf_model.hpp"

namespace microbrdf::fit_detail {

/// Most fit-space parameters of any model (a mixture of two ellipsoids has 11), plus the
/// amplitude.
constexpr int kMaxParams = 15;

// Everything a residual needs: the model, the region of interest, the transformed table, the
// forward operator.
struct FitContext {
  const NdfModel* model = nullptr;
  int k = 0;  // the model's parameters
  FitObjective objective = FitObjective::Sqrt;
  bool tent = false;
  int s = 1;        // tent subsamples
  int threads = 1;  // for the solver's sums
  std::size_t n = 0;
  double delta = 0, eps = 0, lin_scale = 1;
  std::size_t ix0 = 0, ix1 = 0, iy0 = 0, iy1 = 0;
  std::vector<double> gt;  // g(T) on the ROI, row-major

  std::size_t cols() const { return ix1 - ix0 + 1; }
  std::size_t rows() const { return iy1 - iy0 + 1; }
  double ox = -1, oy = -1;  // the table's first node (its window's corner)
  double node_x(std::size_t i) const { return ox + delta * static_cast<double>(i); }
  double node_y(std::size_t i) const { return oy + delta * static_cast<double>(i); }

  /// g(d) and g'(d) of the objective.
  double g0(double d) const {
    switch (objective) {
      case FitObjective::Sqrt:
        return std::sqrt(d + eps);
      case FitObjective::Log:
        return std::log(d + eps);
      case FitObjective::Linear:
        break;
    }
    return d * lin_scale;
  }
  double dg(double d) const {
    switch (objective) {
      case FitObjective::Sqrt:
        return 0.5 / std::sqrt(d + eps);
      case FitObjective::Log:
        return 1 / (d + eps);
      case FitObjective::Linear:
        break;
    }
    return lin_scale;
  }

  /// The model as compared on ROI row iy (absolute node index): values into val[cols()] and,
  /// when grad != nullptr, d/d shape_p into grad[p cols() + c].
  void row_model(const NdfEvaluator& ev, std::size_t iy, double* val, double* grad) const;
  /// 1/2 sum r^2 (rows summed in order: the same number for any thread count).
  double cost(const double* shape, double amp) const;
  /// Node mode: the amplitude that renormalises the point samples on the ROI.
  double node_amplitude(const double* shape) const;
};

/// Effective NDFs inferred from measured BRDFs: absolute, NaN where nothing was measured.
bool measured_table(const TabulatedNdf& t);
/// Point samples (analytic models, Kirchhoff, measured): recorded, or inferred from the method.
bool point_sampled(const TabulatedNdf& t);
/// The context of a fit of o.model starting at `start` (its alphas set the tent subsamples).
FitContext make_context(const TabulatedNdf& t, const FitOptions& o, const NdfModel& model,
                        const std::vector<double>& start);

/// Normal equations of the Gauss-Newton model at one point: J^T J, J^T r (columns: the shape
/// parameters, then log amplitude) and the cost 1/2 r^T r.
struct NormalEq {
  int n = 0;
  double jtj[kMaxParams + 1][kMaxParams + 1] = {}, jtr[kMaxParams + 1] = {}, cost = 0;
};
NormalEq normal_equations(const FitContext& c, const double* shape, double log_amp);

}  // namespace microbrdf::fit_detail
