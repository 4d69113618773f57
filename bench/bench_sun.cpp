// Sun 2002: analytic BRDF evaluations per second (both forms, unit and conductor Fresnel), the
// FTP Gamma_0 alone, and the section 4 FTP simulation in rays per second (profile generation
// included).
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "microbrdf/sun2002.hpp"

using namespace microbrdf::sun2002;

namespace {

std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> random_pairs(std::size_t n) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  auto d = [&] {
    double c = u(rng), s = std::sqrt(1 - c * c), p = 2 * M_PI * u(rng);
    return Eigen::Vector3d(s * std::cos(p), s * std::sin(p), c);
  };
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> v(n);
  for (auto& x : v) x = {d(), d()};
  return v;
}

void BM_SunBrdf(benchmark::State& state) {
  const auto form = state.range(0) ? BrdfForm::Standard : BrdfForm::AsPublished;
  // The shared exact conductor Fresnel (microbrdf::ConductorFresnel, Siegel form).
  const microbrdf::ConductorFresnel conductor(microbrdf::constant_index(0.2, 3.0));
  const microbrdf::Fresnel* F = state.range(1) ? &conductor : nullptr;
  const auto pairs = random_pairs(4096);
  std::size_t i = 0;
  for (auto _ : state) {
    const auto& [wi, wo] = pairs[i++ & 4095];
    benchmark::DoNotOptimize(brdf(wi, wo, 2.0, form, F, 555e-9));
  }
  state.counters["evals/s"] = benchmark::Counter(1, benchmark::Counter::kIsIterationInvariantRate);
  state.SetLabel(std::string(state.range(0) ? "standard" : "as published") +
                 (state.range(1) ? ", conductor Fresnel" : ", R = 1"));
}
BENCHMARK(BM_SunBrdf)->Args({0, 0})->Args({1, 0})->Args({0, 1})->Args({1, 1});

void BM_SunFtp(benchmark::State& state) {
  double t = 0.01;
  for (auto _ : state) {
    benchmark::DoNotOptimize(ftp(t, 1.0));
    t = t > 1.5 ? 0.01 : t + 0.001;
  }
  state.counters["evals/s"] = benchmark::Counter(1, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_SunFtp);

// One s, 91 angles (0..90 deg), 1e4 crossings: rays cast (both directions, all angles) per
// second, wall clock, all threads.
void BM_SunFtpSimulation(benchmark::State& state) {
  FtpSimParams p;
  p.s = static_cast<double>(state.range(0)) / 100;
  p.crossings = 10000;
  for (int d = 0; d <= 90; ++d) p.theta.push_back(d * M_PI / 180);
  double rays = 0;
  for (auto _ : state) {
    const auto r = simulate_ftp(p);
    for (const auto& q : r.points) rays += static_cast<double>(q.rays);
  }
  state.counters["rays/s"] = benchmark::Counter(rays, benchmark::Counter::kIsRate);
  state.SetLabel("s = " + std::to_string(p.s));
}
BENCHMARK(BM_SunFtpSimulation)
    ->Arg(10)
    ->Arg(100)
    ->Arg(500)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
