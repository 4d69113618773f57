// Parametric NDF fits (include/microbrdf/fit.hpp, docs/fitting.md): the starting point, the
// passes of the solver, the bounds, the result and its tables and JSON. The objective is in
// fit_objective.cpp, the solvers in fit_solver.cpp, the models in the registry (ndf_model.hpp).
#include "microbrdf/fit.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "fit/fit_context.hpp"
#include "fit/fit_solver.hpp"
#include "microbrdf/error.hpp"

namespace microbrdf {
namespace {

using fit_detail::FitContext;
using fit_detail::make_context;
using fit_detail::measured_table;
using fit_detail::point_sampled;

constexpr double kPi = 3.14159265358979323846;
constexpr double kThetaTiltMax = 1.2;  // rad, bound on theta_x, theta_y
constexpr double kAlphaMax = 4.0;
constexpr double kLogAmpMax = 3.0;
constexpr double kInf = std::numeric_limits<double>::infinity();

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// Fit-space bounds of the model's parameters then the log amplitude: alphas (log) in
// [la_lo, la_hi], tilts +-kThetaTiltMax, azimuths free, exponents and weights their range.
void fit_bounds(const NdfModel& m, double la_lo, double la_hi, std::vector<double>& lo,
                std::vector<double>& hi) {
  lo.clear();
  hi.clear();
  for (const auto& p : m.params()) {
    switch (p.kind) {
      case NdfParam::Kind::Alpha:
        lo.push_back(la_lo);
        hi.push_back(la_hi);
        break;
      case NdfParam::Kind::Tilt:
        lo.push_back(-kThetaTiltMax);
        hi.push_back(kThetaTiltMax);
        break;
      case NdfParam::Kind::Azimuth:
        lo.push_back(-kInf);
        hi.push_back(kInf);
        break;
      case NdfParam::Kind::Exponent:
        lo.push_back(std::log(std::max(1e-6, 1e-3 * (p.def - p.lo))));
        hi.push_back(std::log(p.hi - p.lo));
        break;
      case NdfParam::Kind::Weight:
        lo.push_back(p.lo);
        hi.push_back(p.hi);
        break;
    }
  }
  lo.push_back(-kLogAmpMax);
  hi.push_back(kLogAmpMax);
}

// Where a fit ended on a bound of its box ("" inside it).
std::string bound_note(const NdfModel& m, const std::vector<double>& s, double la_lo, double la_hi,
                       bool amplitude_free, double log_amp) {
  constexpr double kTol = 1e-6;
  auto value = [](double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.3g", v);
    return std::string(b);
  };
  const auto& ps = m.params();
  // " (alpha_x, alpha_y)": the parameters of one kind that satisfy `at`.
  auto names = [&](NdfParam::Kind kind, auto at) {
    std::string list;
    for (std::size_t i = 0; i < ps.size(); ++i)
      if (ps[i].kind == kind && at(i)) list += (list.empty() ? "" : ", ") + ps[i].name;
    return list.empty() ? list : " (" + list + ")";
  };
  std::vector<std::string> notes;
  std::vector<double> lo, hi;
  fit_bounds(m, la_lo, la_hi, lo, hi);
  const std::string al =
      names(NdfParam::Kind::Alpha, [&](std::size_t i) { return s[i] <= la_lo + kTol; });
  if (!al.empty()) notes.push_back("the lower alpha bound " + value(std::exp(la_lo)) + al);
  const std::string ah =
      names(NdfParam::Kind::Alpha, [&](std::size_t i) { return s[i] >= la_hi - kTol; });
  if (!ah.empty()) notes.push_back("the upper alpha bound " + value(std::exp(la_hi)) + ah);
  const std::string t = names(
      NdfParam::Kind::Tilt, [&](std::size_t i) { return std::abs(s[i]) >= kThetaTiltMax - kTol; });
  if (!t.empty()) notes.push_back("the tilt bound " + value(kThetaTiltMax) + " rad" + t);
  const std::vector<double> v = m.from_fit(s.data());
  for (std::size_t i = 0; i < ps.size(); ++i) {
    const bool other =
        ps[i].kind == NdfParam::Kind::Exponent || ps[i].kind == NdfParam::Kind::Weight;
    if (!other) continue;
    if (s[i] <= lo[i] + kTol)
      notes.push_back("the lower " + ps[i].name + " bound " + value(m.from_fit(lo.data())[i]));
    // (An exponent at its upper bound is the model's limit, e.g. Student-t's Beckmann limit: a
    // result, not a failure.)
    if (s[i] >= hi[i] - kTol && ps[i].kind != NdfParam::Kind::Exponent)
      notes.push_back("the upper " + ps[i].name + " bound " + value(m.from_fit(hi.data())[i]));
  }
  if (amplitude_free && std::abs(log_amp) >= kLogAmpMax - kTol)
    notes.push_back("the amplitude bound exp(" + std::string(log_amp < 0 ? "-" : "") +
                    value(kLogAmpMax) + ")");
  std::string out;
  for (const auto& n : notes) out += (out.empty() ? "" : "; ") + n;
  return out;
}

// The smallest alpha of a fit-space vector (log), +inf without alphas.
double min_log_alpha(const NdfModel& m, const std::vector<double>& s) {
  double out = kInf;
  for (std::size_t i = 0; i < m.params().size(); ++i)
    if (m.params()[i].kind == NdfParam::Kind::Alpha) out = std::min(out, s[i]);
  return out;
}

// The table's slope moments (initial_guess).
NdfMoments moments(const TabulatedNdf& ndf, bool mean_normal) {
  const Eigen::Matrix2d c = ndf.slope_covariance();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(c);
  const Eigen::Vector2d ev = es.eigenvalues();
  const Eigen::Matrix2d vec = es.eigenvectors();
  // The alpha_x axis: the eigenvector nearer +x.
  const int ix = std::abs(vec(0, 0)) >= std::abs(vec(0, 1)) ? 0 : 1;
  const Eigen::Vector2d ax = vec.col(ix);
  double phi = std::atan2(ax.y(), ax.x());
  if (phi > kPi / 2) phi -= kPi;
  if (phi <= -kPi / 2) phi += kPi;
  auto width = [&](double lambda) {
    return std::clamp(std::sqrt(2 * std::max(lambda, 0.0)), 0.25 * ndf.spacing(), kAlphaMax);
  };
  NdfMoments m;
  m.alpha_x = width(ev(ix));
  m.alpha_y = width(ev(1 - ix));
  m.phi = phi;
  if (mean_normal) m.mean_normal = ndf.mean_normal();
  return m;
}

// Rows of a tent-averaged table: `sub_row(x0, h, n, y, out)` gives D at n points of a sub-row.
template <typename SubRow>
TabulatedNdf tent_table(std::size_t resolution, int subsamples, const NdfWindow& window,
                        const SubRow& sub_row_values) {
  if (resolution < 3) throw InputError("NDF table resolution must be at least 3");
  const int s = std::max(1, subsamples);
  const auto ss = static_cast<std::size_t>(s);
  TabulatedNdf t(resolution, window);
  const double delta = t.spacing(), h = delta / s;
  std::vector<double> w(2 * ss);
  for (std::size_t a = 0; a < w.size(); ++a)
    w[a] = (1.0 - std::abs((static_cast<double>(a) + 0.5) / s - 1.0)) / s;
  // The midpoint samples of neighbouring tent cells coincide: D is evaluated once per point of
  // the sub-grid (s (N + 1))^2 (each sub-row's y and sub-column's x from its own index), rows in
  // contiguous bands per thread so that a row reuses the previous row's last s sub-rows.
  const std::size_t nsub = ss * (resolution + 1);
  const double x0 = t.node_x(0) - delta + 0.5 * h, y0 = t.node_y(0) - delta + 0.5 * h;
#pragma omp parallel
  {
    std::vector<double> buf(2 * ss * nsub);
    std::vector<long> held(2 * ss, -1);
    auto sub_row = [&](std::size_t j) -> const double* {
      double* out = &buf[(j % (2 * ss)) * nsub];
      if (held[j % (2 * ss)] == static_cast<long>(j)) return out;
      held[j % (2 * ss)] = static_cast<long>(j);
      sub_row_values(x0, h, nsub, y0 + static_cast<double>(j) * h, out);
      return out;
    };
#pragma omp for schedule(static)
    for (std::size_t iy = 0; iy < resolution; ++iy) {
      double* row = &t.at(0, iy);
      for (std::size_t b = 0; b < 2 * ss; ++b) {
        const double* sr = sub_row(iy * ss + b);
        for (std::size_t ix = 0; ix < resolution; ++ix) {
          double acc = 0;
          for (std::size_t a = 0; a < 2 * ss; ++a) acc += w[a] * sr[ix * ss + a];
          row[ix] += w[b] * acc;
        }
      }
    }
  }
  t.meta.sampling = "cell";
  return t;
}

// `seeded`: starting points (values) from other models' fits (NdfModel::seeded_starts); the one
// of lowest cost is always solved from, besides the model's own starts.
FitResult fit_ndf_single(const TabulatedNdf& ndf, const FitOptions& o,
                         const std::vector<std::vector<double>>& seeded = {}) {
  const auto t0 = std::chrono::steady_clock::now();
  if (ndf.resolution() < 5) throw InputError("NDF table too small to fit");
  const NdfModel& model = ndf_model(o.model);
  const int k = static_cast<int>(model.params().size());
  // Moments for the starting point come from the measured nodes only (NaN -> 0).
  std::vector<std::vector<double>> starts;
  if (o.initial) {
    starts = {model.values(*o.initial)};
  } else if (measured_table(ndf)) {
    TabulatedNdf filled = ndf;
    for (double& v : filled.values())
      if (!(v > 0)) v = 0;
    starts = model.starts(moments(filled, model.has_kind(NdfParam::Kind::Tilt)));
  } else {
    starts = model.starts(moments(ndf, model.has_kind(NdfParam::Kind::Tilt)));
  }
  const double alpha_min = std::max(1e-5, ndf.spacing() / 20);
  for (auto& s : starts)
    for (int i = 0; i < k; ++i)
      if (model.params()[static_cast<std::size_t>(i)].kind == NdfParam::Kind::Alpha)
        s[static_cast<std::size_t>(i)] =
            std::clamp(s[static_cast<std::size_t>(i)], alpha_min, kAlphaMax);
  std::vector<double> start = starts.front();

  FitContext ctx = make_context(ndf, o, model, start);
  std::vector<double> shape = model.to_fit(start);
  auto scale_alphas = [&](std::vector<double>& s, double f) {
    for (int i = 0; i < k; ++i)
      if (model.params()[static_cast<std::size_t>(i)].kind == NdfParam::Kind::Alpha)
        s[static_cast<std::size_t>(i)] =
            std::max(std::log(alpha_min), s[static_cast<std::size_t>(i)] + std::log(f));
  };
  // Multi-start on the model's starting points and the scale of the alphas (moments of
  // heavy-tailed tables overestimate): each start's best scaling, the starts by cost.
  std::vector<std::pair<double, std::vector<double>>> candidates;
  if (!o.initial) {
    for (const auto& st : starts) {
      double best = kInf;
      std::vector<double> best_shape;
      for (double f : {1.0, 0.7, 0.5, 0.35, 0.25, 0.18, 0.125}) {
        std::vector<double> s = model.to_fit(st);
        scale_alphas(s, f);
        const double amp = ctx.tent ? 1.0 : ctx.node_amplitude(s.data());
        const double cst = ctx.cost(s.data(), amp);
        if (cst < best) {
          best = cst;
          best_shape = s;
        }
      }
      candidates.emplace_back(best, best_shape);
    }
    std::stable_sort(candidates.begin(), candidates.end(),
                     [](const auto& x, const auto& y) { return x.first < y.first; });
  } else {
    candidates.emplace_back(0.0, shape);
  }
  // Models with several starts (shape parameters, two lobes: local minima) are solved from the
  // best three and keep the lowest final cost; the others from their one start.
  candidates.resize(std::min<std::size_t>(candidates.size(), 3));
  // The best seeded start (a mixture: typically its better lobe's own fit) is solved from too,
  // so that the result is never above it.
  double best_seeded = kInf;
  std::vector<double> seeded_shape;
  for (auto v : seeded) {
    for (int i = 0; i < k; ++i)
      if (model.params()[static_cast<std::size_t>(i)].kind == NdfParam::Kind::Alpha)
        v[static_cast<std::size_t>(i)] =
            std::clamp(v[static_cast<std::size_t>(i)], alpha_min, kAlphaMax);
    const std::vector<double> s = model.to_fit(v);
    const double cst = ctx.cost(s.data(), ctx.tent ? 1.0 : ctx.node_amplitude(s.data()));
    if (cst < best_seeded) {
      best_seeded = cst;
      seeded_shape = s;
    }
  }
  if (!seeded_shape.empty()) candidates.emplace_back(best_seeded, seeded_shape);
  const FitContext ctx0 = ctx;
  struct Attempt {
    FitResult r;
    std::vector<double> shape;
    double log_amp = 0, la_final = 0;
    FitContext ctx;
  };
  auto attempt = [&](std::vector<double> shape) -> Attempt {
    FitContext ctx = ctx0;
    double log_amp = 0;
    std::vector<double> start = model.from_fit(shape.data());
    if (!o.initial && ctx.tent && o.tent_subsamples <= 0)
      ctx = make_context(ndf, o, model, start);  // subsamples
    if (!ctx.tent) log_amp = std::log(ctx.node_amplitude(shape.data()));

    FitResult r;
    r.model = model.name();
    r.initial = model.named(start);
    r.objective = o.objective;
    r.sampling = ctx.tent ? FitSampling::Tent : FitSampling::Node;
    r.window = ndf.window();
    r.table_sampling = ndf_sampling(ndf.meta);
    r.table_sampling_recorded = ndf_sampling_recorded(ndf.meta);
    r.tent_subsamples = ctx.tent ? ctx.s : 1;
    r.floor = ctx.eps;
    r.residuals = ctx.rows() * ctx.cols();
    r.roi[0] = ctx.ix0;
    r.roi[1] = ctx.ix1;
    r.roi[2] = ctx.iy0;
    r.roi[3] = ctx.iy1;
    // (The library's solver reports the cost of its first evaluation instead: the same number.)
    if (o.solver != FitSolver::LevenbergMarquardt)
      r.initial_cost = ctx.cost(shape.data(), std::exp(log_amp));

    const double la_hi = std::log(kAlphaMax);
    double la_final = std::log(alpha_min);  // the lower alpha bound of the last pass
    std::vector<double> lo, hi;
    // Tent mode resolves lobes down to ~2 quadrature steps: alpha >= 2 Delta / s. A fit that ends
    // on that bound is repeated with twice the subsamples (up to 8).
    for (int pass = 0;; ++pass) {
      const double la_lo =
          std::log(ctx.tent ? std::max(alpha_min, 2 * ctx.delta / ctx.s) : alpha_min);
      la_final = la_lo;
      fit_bounds(model, la_lo, la_hi, lo, hi);
      for (int i = 0; i < k; ++i) {
        const auto u = static_cast<std::size_t>(i);
        if (model.params()[u].kind == NdfParam::Kind::Alpha) shape[u] = std::max(shape[u], la_lo);
      }
      if (o.solver == FitSolver::LevenbergMarquardt) {
        std::vector<double> x = shape;
        x.push_back(log_amp);
        const fit_detail::LmResult lm = fit_detail::levenberg_marquardt(
            ctx, x.data(), !ctx.tent, lo.data(), hi.data(), o.max_iterations);
        if (pass == 0) r.initial_cost = lm.initial_cost;
        std::copy(x.begin(), x.begin() + k, shape.begin());
        log_amp = x[static_cast<std::size_t>(k)];
        r.iterations = lm.iterations;
        r.converged = lm.converged;
        r.termination = lm.message;
        r.final_cost = lm.cost;
      } else if (o.solver == FitSolver::CeresAutodiff) {
        const fit_detail::LmResult cr = fit_detail::ceres_solve(
            ctx, shape.data(), &log_amp, lo.data(), hi.data(), o.max_iterations, o.threads);
        r.iterations = cr.iterations;
        r.converged = cr.converged;
        r.termination = cr.message;
        r.final_cost = cr.cost;
      } else {
        std::vector<double> x = shape;
        if (!ctx.tent) x.push_back(log_amp);
        std::vector<double> step(x.size(), 0.02);
        for (int i = 0; i < k; ++i) {
          const auto kind = model.params()[static_cast<std::size_t>(i)].kind;
          if (kind == NdfParam::Kind::Alpha || kind == NdfParam::Kind::Exponent)
            step[static_cast<std::size_t>(i)] = 0.1;
        }
        auto clamped = [&](const std::vector<double>& v) {
          std::vector<double> s(v.begin(), v.begin() + k);
          for (std::size_t i = 0; i < s.size(); ++i) s[i] = std::clamp(s[i], lo[i], hi[i]);
          return s;
        };
        auto f = [&](const std::vector<double>& v) {
          const double amp =
              ctx.tent ? 1.0 : std::exp(std::clamp(v.back(), -kLogAmpMax, kLogAmpMax));
          return ctx.cost(clamped(v).data(), amp);
        };
        double fb = 0;
        bool conv = false;
        r.iterations = fit_detail::nelder_mead(f, x, step, 200 * o.max_iterations, fb, conv);
        shape = clamped(x);
        if (!ctx.tent) log_amp = std::clamp(x.back(), -kLogAmpMax, kLogAmpMax);
        r.final_cost = fb;
        r.converged = conv;
        r.termination = "Nelder-Mead";
      }
      const bool at_bound = min_log_alpha(model, shape) <= la_lo + 1e-6;
      if (!(ctx.tent && at_bound && ctx.s < 8 && pass < 3)) break;
      ctx.s = std::min(8, 2 * ctx.s);
      r.tent_subsamples = ctx.s;
    }
    return Attempt{r, shape, log_amp, la_final, ctx};
  };
  Attempt best;
  best.r.final_cost = kInf;
  for (const auto& c : candidates) {
    Attempt a = attempt(c.second);
    if (!(a.r.final_cost >= best.r.final_cost)) best = std::move(a);
  }
  FitResult r = best.r;
  std::vector<double> shape_final = best.shape;
  const double log_amp_final = best.log_amp, la_final = best.la_final;
  const FitContext& ctx_final = best.ctx;
  r.solver_converged = r.converged;
  r.at_bound =
      bound_note(model, shape_final, la_final, std::log(kAlphaMax), !ctx_final.tent, log_amp_final);
  if (!r.at_bound.empty()) r.converged = false;
  std::vector<double> values = model.from_fit(shape_final.data());
  model.canonicalise(values);
  r.params = model.named(values);
  r.amplitude = std::exp(log_amp_final);
  r.phi = r.params.get("phi", 0.0);

  // Errors over the whole disk.
  const TabulatedNdf m = fit_table(r, ndf.resolution());
  double se = 0, st = 0, sh = 0;
  std::size_t count = 0;
  for (std::size_t iy = 0; iy < ndf.resolution(); ++iy)
    for (std::size_t ix = 0; ix < ndf.resolution(); ++ix) {
      const double x = ndf.node_x(ix), y = ndf.node_y(iy);
      if (x * x + y * y >= 1 || std::isnan(ndf.at(ix, iy))) continue;  // unmeasured
      const double tv = std::max(0.0, ndf.at(ix, iy)), mv = m.at(ix, iy);
      se += (tv - mv) * (tv - mv);
      st += tv * tv;
      const double dh = std::sqrt(tv) - std::sqrt(mv);
      sh += dh * dh;
      ++count;
    }
  r.rms_error = std::sqrt(se / static_cast<double>(std::max<std::size_t>(count, 1)));
  r.relative_l2_error = st > 0 ? std::sqrt(se / st) : 0.0;
  r.hellinger = std::sqrt(0.5 * sh * ndf.spacing() * ndf.spacing());
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

// The table at (N - 1) / 4 + 1 nodes, as the estimator would have made it there: tent tables
// (histograms) are restricted with the tent weights (1 - |a|/4)/4, a = -3..3 per axis (the
// coarse hat functions are these sums of fine ones, so mass and shape are kept exactly); node
// tables (point samples of a model) keep every fourth node.
TabulatedNdf coarsened(const TabulatedNdf& t, bool tent) {
  const std::size_t n = t.resolution(), nc = (n - 1) / 4 + 1;
  TabulatedNdf c(nc, t.window());
  c.meta = t.meta;
  const double w[7] = {0.0625, 0.125, 0.1875, 0.25, 0.1875, 0.125, 0.0625};
#pragma omp parallel for schedule(static)
  for (std::size_t iy = 0; iy < nc; ++iy)
    for (std::size_t ix = 0; ix < nc; ++ix) {
      if (!tent) {
        c.at(ix, iy) = t.at(4 * ix, 4 * iy);
        continue;
      }
      double acc = 0;
      for (int b = -3; b <= 3; ++b) {
        const long y = 4 * static_cast<long>(iy) + b;
        if (y < 0 || y >= static_cast<long>(n)) continue;
        for (int a = -3; a <= 3; ++a) {
          const long x = 4 * static_cast<long>(ix) + a;
          if (x < 0 || x >= static_cast<long>(n)) continue;
          acc +=
              w[b + 3] * w[a + 3] * t.at(static_cast<std::size_t>(x), static_cast<std::size_t>(y));
        }
      }
      c.at(ix, iy) = acc;
    }
  return c;
}

}  // namespace

FitObjective parse_fit_objective(const std::string& name) {
  const std::string m = lower(name);
  if (m == "sqrt") return FitObjective::Sqrt;
  if (m == "linear") return FitObjective::Linear;
  if (m == "log") return FitObjective::Log;
  throw InputError("unknown objective '" + name + "' (sqrt | linear | log)");
}
std::string fit_objective_name(FitObjective o) {
  return o == FitObjective::Sqrt ? "sqrt" : o == FitObjective::Linear ? "linear" : "log";
}
FitSampling parse_fit_sampling(const std::string& name) {
  const std::string m = lower(name);
  if (m == "auto") return FitSampling::Auto;
  if (m == "node") return FitSampling::Node;
  if (m == "tent") return FitSampling::Tent;
  throw InputError("unknown sampling '" + name + "' (auto | node | tent)");
}
std::string fit_sampling_name(FitSampling s) {
  return s == FitSampling::Auto ? "auto" : s == FitSampling::Node ? "node" : "tent";
}

std::string parse_fit_model(const std::string& name) { return ndf_model(name).name(); }

NdfParams initial_guess(const TabulatedNdf& ndf, const std::string& name) {
  const NdfModel& model = ndf_model(name);
  return model.named(model.initial(moments(ndf, model.has_kind(NdfParam::Kind::Tilt))));
}

double fit_objective(const TabulatedNdf& ndf, const FitOptions& o, const NdfParams& p,
                     double amplitude) {
  const NdfModel& model = ndf_model(o.model);
  const std::vector<double> v = model.values(p);
  const FitContext c = make_context(ndf, o, model, v);
  return c.cost(model.to_fit(v).data(), c.tent ? 1.0 : amplitude);
}

namespace {

FitResult fit_ndf_unseeded(const TabulatedNdf& ndf, const FitOptions& o,
                           const std::vector<std::vector<double>>& seeded) {
  // Coarse to fine: on large tables whose lobe the quarter-resolution table still resolves (the
  // moment guess at least three coarse spacings wide), the multi-start and the first iterations
  // run on the coarse table; its optimum starts the fit on the full table, which converges to
  // the full table's own optimum.
  const std::size_t n = ndf.resolution();
  if (o.solver == FitSolver::LevenbergMarquardt && !o.initial && n >= 513 && (n - 1) % 4 == 0 &&
      !measured_table(ndf)) {
    const auto t0 = std::chrono::steady_clock::now();
    const NdfModel& model = ndf_model(o.model);
    const std::vector<double> g = model.values(initial_guess(ndf, o.model));
    const double coarse_spacing = 4 * ndf.spacing();
    if (std::exp(min_log_alpha(model, model.to_fit(g))) >= 3 * coarse_spacing) {
      FitSampling smp = o.sampling;
      if (smp == FitSampling::Auto)
        smp = point_sampled(ndf) ? FitSampling::Node : FitSampling::Tent;
      const TabulatedNdf coarse = coarsened(ndf, smp == FitSampling::Tent);
      FitOptions co = o;
      co.sampling = smp;
      const FitResult c = fit_ndf_single(coarse, co);
      FitOptions fo = o;
      fo.initial = c.params;
      FitResult r = fit_ndf_single(ndf, fo, seeded);
      // (Started from the coarse optimum rather than a seeded start: the coarse fit's start.)
      const auto& a = r.initial.values;
      const auto& b = c.params.values;
      if (a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](double x, double y) {
            return std::abs(x - y) <= 1e-9 * (1 + std::abs(y));
          }))
        r.initial = c.initial;
      r.iterations += c.iterations;
      r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      return r;
    }
  }
  return fit_ndf_single(ndf, o, seeded);
}

}  // namespace

FitResult fit_ndf(const TabulatedNdf& ndf, const FitOptions& o) {
  const auto t_start = std::chrono::steady_clock::now();
  // Models seeded by other models' fits (mixtures by their lobes'): those fits first.
  const NdfModel& fitted_model = ndf_model(o.model);
  std::vector<std::vector<double>> seeded;
  if (!o.initial && !fitted_model.seeds().empty()) {
    std::vector<std::vector<double>> fitted;
    std::vector<std::pair<std::string, std::vector<double>>> done;  // a model seeding twice
    for (const NdfModel* s : fitted_model.seeds()) {
      auto it = std::find_if(done.begin(), done.end(),
                             [&](const auto& d) { return d.first == s->name(); });
      if (it == done.end()) {
        FitOptions so = o;
        so.model = s->name();
        done.emplace_back(s->name(), s->values(fit_ndf(ndf, so).params));
        it = done.end() - 1;
      }
      fitted.push_back(it->second);
    }
    seeded = fitted_model.seeded_starts(fitted);
  }
  FitResult r = fit_ndf_unseeded(ndf, o, seeded);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  return r;
}

std::shared_ptr<MicrofacetDistribution> fitted_distribution(const FitResult& r) {
  const NdfModel& model = ndf_model(r.model);
  return model.make(model.values(r.params));
}

TabulatedNdf tabulate_tent(const MicrofacetDistribution& d, const std::string& model,
                           std::size_t resolution, int subsamples, const NdfWindow& window) {
  TabulatedNdf t = tent_table(resolution, subsamples, window,
                              [&](double x0, double h, std::size_t n, double y, double* out) {
                                for (std::size_t i = 0; i < n; ++i) {
                                  const double x = x0 + static_cast<double>(i) * h,
                                               r2 = x * x + y * y;
                                  out[i] = r2 < 1 ? d.D(Vec3(x, y, std::sqrt(1 - r2))) : 0.0;
                                }
                              });
  t.meta.method = model + "-tent";
  t.meta.notes = d.describe() + "; tent-cell averages, " + std::to_string(std::max(1, subsamples)) +
                 " subsamples";
  return t;
}

TabulatedNdf fit_table(const FitResult& r, std::size_t resolution) {
  // D from the model's own evaluator (no distribution needed: mixtures have none).
  const NdfModel& model = ndf_model(r.model);
  const std::vector<double> fit = model.to_fit(model.values(r.params));
  const auto ev = model.evaluator(fit.data(), false);
  TabulatedNdf t(resolution, r.window);
  if (r.sampling == FitSampling::Tent) {
    t = tent_table(resolution, r.tent_subsamples, r.window,
                   [&](double x0, double h, std::size_t n, double y, double* out) {
                     ev->row(x0, h, n, y, out, nullptr, 0);
                   });
  } else {
    t.meta.sampling = "point";
    for (std::size_t iy = 0; iy < resolution; ++iy) {
      double* row = &t.at(0, iy);
      ev->row(t.node_x(0), t.spacing(), resolution, t.node_y(iy), row, nullptr, 0);
      for (std::size_t ix = 0; ix < resolution; ++ix) row[ix] *= r.amplitude;
    }
  }
  t.meta.method = r.model + " fit";
  t.meta.notes = r.model + " " + model.params_json(model.values(r.params)).dump();
  return t;
}

nlohmann::json fit_result_json(const FitResult& r) {
  const NdfModel& model = ndf_model(r.model);
  const nlohmann::json params = model.params_json(model.values(r.params));
  nlohmann::json deg = nlohmann::json::object();
  for (const char* a : {"theta_x", "theta_y", "theta_z", "phi"})
    if (params.contains(a)) deg[a] = params[a].get<double>() * 180 / kPi;
  return {
      {"model", r.model},
      {"params", params},
      {"params_deg", deg},
      {"phi", r.phi},
      {"rms_error", r.rms_error},
      {"relative_l2_error", r.relative_l2_error},
      {"hellinger", r.hellinger},
      {"amplitude", r.amplitude},
      {"objective", fit_objective_name(r.objective)},
      {"sampling", fit_sampling_name(r.sampling)},
      {"table_sampling", r.table_sampling},
      {"table_sampling_recorded", r.table_sampling_recorded},
      {"window", {{"x", {r.window.x0(), r.window.x1()}}, {"y", {r.window.y0(), r.window.y1()}}}},
      {"tent_subsamples", r.tent_subsamples},
      {"floor", r.floor},
      {"initial_params", model.params_json(model.values(r.initial))},
      {"initial_cost", r.initial_cost},
      {"final_cost", r.final_cost},
      {"iterations", r.iterations},
      {"converged", r.converged},
      {"solver_converged", r.solver_converged},
      {"at_bound", r.at_bound.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.at_bound)},
      {"termination", r.termination},
      {"residuals", r.residuals},
      {"roi", {r.roi[0], r.roi[1], r.roi[2], r.roi[3]}},
      {"seconds", r.seconds}};
}

}  // namespace microbrdf
