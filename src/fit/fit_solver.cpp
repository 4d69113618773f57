// The fit's solvers (fit_solver.hpp): Levenberg-Marquardt on the closed-form normal
// equations, Nelder-Mead, and Ceres on the models' automatic derivatives.
#include "fit/fit_solver.hpp"

#include <ceres/ceres.h>
#include <omp.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

namespace microbrdf::fit_detail {

// Levenberg-Marquardt on the normal equations of fit_context.hpp, with box bounds by projection:
// the solver's stopping rules are those given to Ceres before (relative cost change 1e-13, gradient
// 1e-14, relative step 1e-11). x: shape then log amplitude (fixed when !amp_free).
LmResult levenberg_marquardt(const FitContext& c, double* x, bool amp_free, const double* lo,
                             const double* hi, int max_iterations) {
  const int k = c.k, np = k + 1, nf = amp_free ? np : k;
  LmResult out;
  NormalEq e = normal_equations(c, x, x[k]);
  out.initial_cost = e.cost;
  double lambda = 1e-4;
  // The histogram residuals do not vanish at the optimum, so Gauss-Newton alone converges only
  // linearly there. S approximates the rest of the Hessian, sum r_i grad^2 r_i, by the
  // structured secant update of Dennis, Gay and Welsch (NL2SOL): after each accepted step s,
  // S s = y#, y# = (J+^T r+ - J^T r) - J+^T J+ s. Steps solve (J^T J + tau S + lambda D) d = -g.
  Eigen::MatrixXd sm = Eigen::MatrixXd::Zero(nf, nf);
  int rejected_in_row = 0;
  out.message = "no iterations";
  for (int it = 0; it < max_iterations; ++it) {
    ++out.iterations;
    Eigen::MatrixXd jtj(nf, nf);
    Eigen::VectorXd g(nf);
    double gmax = 0;
    for (int p = 0; p < nf; ++p) {
      g(p) = e.jtr[p];
      // Projected gradient: a bound that blocks the descent direction does not count.
      const bool blocked = (x[p] <= lo[p] && e.jtr[p] > 0) || (x[p] >= hi[p] && e.jtr[p] < 0);
      if (!blocked) gmax = std::max(gmax, std::abs(e.jtr[p]));
      for (int q = 0; q < nf; ++q) jtj(p, q) = e.jtj[p][q];
    }
    if (gmax <= 1e-14) {
      out.converged = true;
      out.message = "Gradient tolerance reached.";
      break;
    }
    // Active set: a parameter on a bound whose descent direction leaves the box is held there
    // for this step (the reduced system is solved for the others).
    std::vector<int> fr;
    for (int p = 0; p < nf; ++p) {
      const bool blocked = (x[p] <= lo[p] && e.jtr[p] > 0) || (x[p] >= hi[p] && e.jtr[p] < 0);
      if (!blocked) fr.push_back(p);
    }
    const int nr = static_cast<int>(fr.size());
    Eigen::MatrixXd a(nr, nr), ag(nr, nr);
    Eigen::VectorXd gr(nr);
    for (int i = 0; i < nr; ++i) {
      gr(i) = g(fr[static_cast<std::size_t>(i)]);
      for (int j = 0; j < nr; ++j) {
        const int p = fr[static_cast<std::size_t>(i)], q = fr[static_cast<std::size_t>(j)];
        ag(i, j) = jtj(p, q);
        a(i, j) = jtj(p, q) + sm(p, q);
      }
      const int p = fr[static_cast<std::size_t>(i)];
      a(i, i) += lambda * std::max(e.jtj[p][p], 1e-30);
      ag(i, i) += lambda * std::max(e.jtj[p][p], 1e-30);
    }
    Eigen::LDLT<Eigen::MatrixXd> ldlt(a);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0)) {
      sm.setZero();  // the secant term made the model indefinite: Gauss-Newton again
      ldlt.compute(ag);
    }
    const Eigen::VectorXd sr = ldlt.solve(-gr);
    Eigen::VectorXd step = Eigen::VectorXd::Zero(nf);
    for (int i = 0; i < nr; ++i) step(fr[static_cast<std::size_t>(i)]) = sr(i);
    double xn[kMaxParams + 1];
    double step_norm = 0, x_norm = 0;
    for (int p = 0; p < np; ++p) {
      xn[p] = x[p];
      if (p < nf) xn[p] = std::clamp(x[p] + step(p), lo[p], hi[p]);
      step_norm += (xn[p] - x[p]) * (xn[p] - x[p]);
      x_norm += x[p] * x[p];
    }
    if (std::sqrt(step_norm) <= 1e-11 * (std::sqrt(x_norm) + 1e-11)) {
      out.converged = true;
      out.message = "Parameter tolerance reached.";
      break;
    }
    const NormalEq en = normal_equations(c, xn, xn[k]);
    if (std::isfinite(en.cost) && en.cost < e.cost) {
      const double change = (e.cost - en.cost) / e.cost;
      // Secant update of S (symmetric; skipped when the curvature along s is not positive).
      Eigen::VectorXd sv(nf), y(nf), jn_s(nf);
      for (int p = 0; p < nf; ++p) {
        sv(p) = xn[p] - x[p];
        y(p) = en.jtr[p] - e.jtr[p];
      }
      for (int p = 0; p < nf; ++p) {
        jn_s(p) = 0;
        for (int q = 0; q < nf; ++q) jn_s(p) += en.jtj[p][q] * sv(q);
      }
      const double ys = y.dot(sv);
      if (ys > 0) {
        // Size S down when it overstates the curvature along s (NL2SOL's tau).
        const double sss = sv.dot(sm * sv);
        const Eigen::VectorXd ysharp = y - jn_s;
        if (sss > 0) sm *= std::min(1.0, std::abs(sv.dot(ysharp)) / sss);
        const Eigen::VectorXd rr = ysharp - sm * sv;
        sm += (rr * y.transpose() + y * rr.transpose()) / ys -
              (rr.dot(sv) / (ys * ys)) * (y * y.transpose());
      }
      std::copy(xn, xn + np, x);
      e = en;
      lambda = std::max(lambda / 3, 1e-12);
      rejected_in_row = 0;
      if (change <= 1e-13) {
        out.converged = true;
        out.message = "Function tolerance reached.";
        break;
      }
    } else {
      lambda *= 4;
      if (++rejected_in_row >= 2) sm.setZero();
      if (lambda > 1e16) {
        out.converged = true;
        out.message = "No further decrease of the cost.";
        break;
      }
    }
    if (it + 1 == max_iterations) out.message = "Maximum number of iterations reached.";
  }
  out.cost = e.cost;
  return out;
}

// Nelder-Mead on the same objective (reference solver; bounds by clamping).
int nelder_mead(const std::function<double(const std::vector<double>&)>& f, std::vector<double>& x,
                const std::vector<double>& step, int max_evals, double& fbest, bool& converged) {
  converged = false;
  const std::size_t n = x.size();
  std::vector<std::vector<double>> pts(n + 1, x);
  std::vector<double> fv(n + 1);
  for (std::size_t i = 0; i < n; ++i) pts[i + 1][i] += step[i];
  int evals = 0;
  for (std::size_t i = 0; i <= n; ++i) {
    fv[i] = f(pts[i]);
    ++evals;
  }
  int iter = 0;
  while (evals < max_evals) {
    ++iter;
    std::vector<std::size_t> idx(n + 1);
    for (std::size_t i = 0; i <= n; ++i) idx[i] = i;
    std::sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return fv[a] < fv[b]; });
    const std::size_t best = idx[0], worst = idx[n], second = idx[n - 1];
    double spread = 0;  // simplex size in parameter units (log alpha, rad)
    for (std::size_t i = 0; i <= n; ++i)
      for (std::size_t j = 0; j < n; ++j)
        spread = std::max(spread, std::abs(pts[i][j] - pts[best][j]));
    if (spread < 1e-8) {
      converged = true;
      break;
    }
    std::vector<double> cen(n, 0.0);
    for (std::size_t i = 0; i <= n; ++i)
      if (i != worst)
        for (std::size_t j = 0; j < n; ++j) cen[j] += pts[i][j] / static_cast<double>(n);
    auto along = [&](double t) {
      std::vector<double> p(n);
      for (std::size_t j = 0; j < n; ++j) p[j] = cen[j] + t * (pts[worst][j] - cen[j]);
      return p;
    };
    auto xr = along(-1);
    const double fr = f(xr);
    ++evals;
    if (fr < fv[best]) {
      auto xe = along(-2);
      const double fe = f(xe);
      ++evals;
      if (fe < fr) {
        pts[worst] = xe;
        fv[worst] = fe;
      } else {
        pts[worst] = xr;
        fv[worst] = fr;
      }
    } else if (fr < fv[second]) {
      pts[worst] = xr;
      fv[worst] = fr;
    } else {
      auto xc = fr < fv[worst] ? along(-0.5) : along(0.5);
      const double fc = f(xc);
      ++evals;
      if (fc < std::min(fr, fv[worst])) {
        pts[worst] = xc;
        fv[worst] = fc;
      } else {
        for (std::size_t i = 0; i <= n; ++i)
          if (i != best) {
            for (std::size_t j = 0; j < n; ++j)
              pts[i][j] = pts[best][j] + 0.5 * (pts[i][j] - pts[best][j]);
            fv[i] = f(pts[i]);
            ++evals;
          }
      }
    }
  }
  const std::size_t b =
      static_cast<std::size_t>(std::min_element(fv.begin(), fv.end()) - fv.begin());
  x = pts[b];
  fbest = fv[b];
  return iter;
}

namespace {

// One ROI row of residuals for Ceres, with the Jacobian from the model's reference (automatic)
// derivatives: parameter blocks (shape, log amplitude).
class RowCost final : public ceres::CostFunction {
 public:
  RowCost(const FitContext& c, std::size_t iy) : c_(c), iy_(iy) {
    set_num_residuals(static_cast<int>(c.cols()));
    mutable_parameter_block_sizes()->push_back(c.k);
    mutable_parameter_block_sizes()->push_back(1);
  }
  bool Evaluate(double const* const* p, double* r, double** jac) const override {
    const std::size_t nc = c_.cols(), k = static_cast<std::size_t>(c_.k);
    const auto ev = c_.model->evaluator(p[0], true);
    std::vector<double> v(nc), g(jac && jac[0] ? k * nc : 0);
    c_.row_model(*ev, iy_, v.data(), g.empty() ? nullptr : g.data());
    const double amp = std::exp(p[1][0]);
    const double* gt_row = &c_.gt[(iy_ - c_.iy0) * nc];
    for (std::size_t col = 0; col < nc; ++col) {
      const bool unmeasured = std::isnan(gt_row[col]);
      const double d = v[col] * amp;
      r[col] = unmeasured ? 0.0 : (c_.g0(d) - gt_row[col]) * c_.delta;
      const double dg = unmeasured ? 0.0 : c_.dg(d) * c_.delta;
      if (jac && jac[0])
        for (std::size_t q = 0; q < k; ++q) jac[0][col * k + q] = dg * amp * g[q * nc + col];
      if (jac && jac[1]) jac[1][col] = dg * d;
    }
    return true;
  }

 private:
  const FitContext& c_;
  std::size_t iy_;
};

}  // namespace

LmResult ceres_solve(const FitContext& ctx, double* shape, double* log_amp, const double* lo,
                     const double* hi, int max_iterations, int threads) {
  ceres::Problem problem;
  for (std::size_t iy = ctx.iy0; iy <= ctx.iy1; ++iy)
    problem.AddResidualBlock(new RowCost(ctx, iy), nullptr, shape, log_amp);
  if (ctx.tent) {
    problem.SetParameterBlockConstant(log_amp);
  } else {
    problem.SetParameterLowerBound(log_amp, 0, lo[ctx.k]);
    problem.SetParameterUpperBound(log_amp, 0, hi[ctx.k]);
  }
  for (int i = 0; i < ctx.k; ++i) {
    if (std::isfinite(lo[i])) problem.SetParameterLowerBound(shape, i, lo[i]);
    if (std::isfinite(hi[i])) problem.SetParameterUpperBound(shape, i, hi[i]);
  }
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
  so.max_num_iterations = max_iterations;
  so.function_tolerance = 1e-13;
  so.gradient_tolerance = 1e-14;
  so.parameter_tolerance = 1e-11;
  so.num_threads = threads > 0 ? threads : omp_get_max_threads();
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;
  ceres::Solver::Summary sum;
  ceres::Solve(so, &problem, &sum);
  LmResult out;
  out.iterations = sum.num_successful_steps + sum.num_unsuccessful_steps;
  out.converged = sum.termination_type == ceres::CONVERGENCE;
  out.message = sum.message;
  out.cost = sum.final_cost;
  out.initial_cost = sum.initial_cost;
  return out;
}

}  // namespace microbrdf::fit_detail
