// NDF fits. The library's Levenberg-Marquardt (closed-form Jacobians, coarse to fine) against two
// references on the same objective in the same run: Ceres' Levenberg-Marquardt with automatic
// derivatives (the previous solver) and Nelder-Mead. Synthetic tables: tabulated analytic models
// (node sampling) with stainless-#4-like widths at N = 257 and 1025, the ellipsoid skewed. Real
// scan: the three fits of `predict` (ellipsoid, Beckmann, GGX; tent sampling) on the filtered
// 1025^2 NDF of tests/data/sample-land.x3p (plane levelled, filter sigma 1 um), as predict does.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <fstream>

#include "bench_load.hpp"
#include "microbrdf/fit.hpp"
#include "microbrdf/io.hpp"
#include "microbrdf/level.hpp"
#include "microbrdf/ndf_estimate.hpp"

using namespace microbrdf;

namespace {

TabulatedNdf table(const std::string& m, std::size_t n) {
  NdfSpec s;
  s.model = m;
  s.alpha_x = 0.03;
  s.alpha_y = 0.14;
  if (m == "ellipsoid") {
    s.theta_x = 0.03;
    s.theta_y = -0.02;
    s.theta_z = 0.1;
  } else {
    s.phi = -0.1;
  }
  return tabulate(*make_distribution(s), s.model, n);
}

void run(benchmark::State& state, const std::string& m, FitSolver solver) {
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  const TabulatedNdf t = table(m, n);
  FitOptions o;
  o.model = m;
  o.solver = solver;
  FitResult r;
  for (auto _ : state) {
    r = fit_ndf(t, o);
    // Keep the fit alive through an int field: DoNotOptimize on a non-const lvalue tells the
    // compiler the value may have been rewritten (a "+r"/"+m" operand), and on a double the
    // reported alpha_x below could then come from a clobbered register (bench_texture.cpp fixed
    // the same pattern).
    benchmark::DoNotOptimize(r.iterations);
  }
  const double alpha_x = r.params.at("alpha_x");
  state.counters["fits_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["residuals"] = static_cast<double>(r.residuals);
  state.counters["iterations"] = r.iterations;
  state.counters["alpha_x_err_ppm"] = std::abs(alpha_x / 0.03 - 1) * 1e6;
}

void BM_FitLM_Ellipsoid(benchmark::State& s) { run(s, "ellipsoid", FitSolver::LevenbergMarquardt); }
void BM_FitLM_Beckmann(benchmark::State& s) { run(s, "beckmann", FitSolver::LevenbergMarquardt); }
void BM_FitLM_Ggx(benchmark::State& s) { run(s, "ggx", FitSolver::LevenbergMarquardt); }
void BM_FitNelderMead_Ellipsoid(benchmark::State& s) { run(s, "ellipsoid", FitSolver::NelderMead); }
void BM_FitNelderMead_Beckmann(benchmark::State& s) { run(s, "beckmann", FitSolver::NelderMead); }
void BM_FitNelderMead_Ggx(benchmark::State& s) { run(s, "ggx", FitSolver::NelderMead); }
void BM_FitCeres_Ellipsoid(benchmark::State& s) { run(s, "ellipsoid", FitSolver::CeresAutodiff); }
void BM_FitCeres_Beckmann(benchmark::State& s) { run(s, "beckmann", FitSolver::CeresAutodiff); }
void BM_FitCeres_Ggx(benchmark::State& s) { run(s, "ggx", FitSolver::CeresAutodiff); }

const TabulatedNdf& land() {
  static const TabulatedNdf t = [] {
    Surface s = read_surface(std::string(MICROBRDF_TEST_DATA) + "/sample-land.x3p");
    level_surface(s, LevelingSpec{});
    NdfEstimateOptions o;
    o.filter_sigma_m = 1e-6;
    return estimate_ndf(s, o);
  }();
  return t;
}

using microbrdf::bench::load_average;

// The three fits of predict on a real scan, with the library's solver (0) or Ceres (1), on the
// given number of threads; counters: seconds per model, and the parameter changes of the
// library's solver against Ceres.
void BM_PredictFitsRealScan(benchmark::State& state) {
  const TabulatedNdf& t = land();
  const bool ceres = state.range(0) != 0;
  const int threads = static_cast<int>(state.range(1));
  const double load0 = load_average();
  double sec[3] = {0, 0, 0};
  FitResult res[3];
  for (auto _ : state) {
    int i = 0;
    for (const char* m : {"ellipsoid", "beckmann", "ggx"}) {
      FitOptions o;
      o.model = m;
      o.solver = ceres ? FitSolver::CeresAutodiff : FitSolver::LevenbergMarquardt;
      o.threads = threads;
      const auto t0 = std::chrono::steady_clock::now();
      res[i] = fit_ndf(t, o);
      sec[i] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      benchmark::DoNotOptimize(res[i].iterations);
      ++i;
    }
  }
  state.counters["ellipsoid_s"] = sec[0];
  state.counters["beckmann_s"] = sec[1];
  state.counters["ggx_s"] = sec[2];
  state.counters["iterations"] = res[0].iterations + res[1].iterations + res[2].iterations;
  if (!ceres) {
    // Largest relative change of alpha_x, alpha_y and absolute change of the angles (rad) against
    // the Ceres reference fits, run here in the same process.
    double da = 0, dt = 0;
    for (int i = 0; i < 3; ++i) {
      FitOptions o;
      o.model = res[i].model;
      o.solver = FitSolver::CeresAutodiff;
      const FitResult c = fit_ndf(t, o);
      const auto& p = res[i].params;
      const auto& q = c.params;
      for (std::size_t k = 0; k < p.size(); ++k) {
        if (p.names[k].rfind("alpha", 0) == 0)
          da = std::max(da, std::abs(p.values[k] / q.values[k] - 1));
        else
          dt = std::max(dt, std::abs(p.values[k] - q.values[k]));
      }
    }
    state.counters["max_rel_dalpha"] = da;
    state.counters["max_dtheta_rad"] = dt;
  }
  state.counters["load_before"] = load0;
  state.counters["load_after"] = load_average();
}

}  // namespace

BENCHMARK(BM_FitLM_Ellipsoid)->Arg(257)->Arg(1025)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FitLM_Beckmann)->Arg(257)->Arg(1025)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FitLM_Ggx)->Arg(257)->Arg(1025)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FitNelderMead_Ellipsoid)->Arg(257)->Arg(1025)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FitNelderMead_Beckmann)->Arg(257)->Arg(1025)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FitNelderMead_Ggx)->Arg(257)->Arg(1025)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FitCeres_Ellipsoid)->Arg(257)->Arg(1025)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FitCeres_Beckmann)->Arg(257)->Arg(1025)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FitCeres_Ggx)->Arg(257)->Arg(1025)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PredictFitsRealScan)
    ->Args({0, 1})
    ->Args({0, 2})
    ->Args({1, 2})
    ->Iterations(1)
    ->UseRealTime()
    ->Unit(benchmark::kSecond);
