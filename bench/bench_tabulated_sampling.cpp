// Sampling a tabulated NDF inside MicrofacetBrdf: the approximate visible-normal sampler
// (TabulatedSampling::Visible) next to the plain D(m)(m.n) sampler (TabulatedSampling::Ndf, the
// reference) on the same 1025^2 table, and the construction time of both.
// Counters: samples/s of MicrofacetBrdf::sample (sample_visible + sampling_pdf + G2 + Fresnel),
// the per-sample weight variance of the albedo estimator (perfect mirror), and the efficiency
// 1 / (variance x time per sample) -- the figure that matters for noise at equal render time.
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "microbrdf/fresnel.hpp"
#include "microbrdf/microfacet.hpp"
#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/tabulated_distribution.hpp"

using namespace microbrdf;

namespace {

// Brushed-metal-like anisotropic Beckmann (alpha 0.02 x 0.3) tabulated on 1025^2.
const TabulatedNdf& brushed_table() {
  static const TabulatedNdf t = [] {
    NdfSpec s;
    s.model = "beckmann";
    s.alpha_x = 0.02;
    s.alpha_y = 0.3;
    s.phi = 0.5;
    return tabulate(*make_distribution(s), "beckmann", 1025);
  }();
  return t;
}

std::shared_ptr<TabulatedDistribution> make(TabulatedSampling s) {
  TabulatedDistributionOptions o;
  o.sampling = s;
  return std::make_shared<TabulatedDistribution>(brushed_table(), o);
}

const std::shared_ptr<TabulatedDistribution>& dist(TabulatedSampling s) {
  static const auto vis = make(TabulatedSampling::Visible);
  static const auto ndf = make(TabulatedSampling::Ndf);
  return s == TabulatedSampling::Visible ? vis : ndf;
}

// state.range(0): 0 = ndf (reference), 1 = visible. state.range(1): theta_i in degrees.
void BM_TabulatedBrdfSample(benchmark::State& state) {
  const auto s = state.range(0) ? TabulatedSampling::Visible : TabulatedSampling::Ndf;
  const MicrofacetBrdf b(dist(s), std::make_shared<PerfectMirrorFresnel>());
  const double th = static_cast<double>(state.range(1)) * M_PI / 180, ph = 70 * M_PI / 180;
  const Vec3 wi(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> us(2 * 4096);
  for (double& x : us) x = u(rng);
  double s1 = 0, s2 = 0, n = 0;
  for (auto _ : state) {
    for (std::size_t i = 0; i < 4096; ++i) {
      auto smp = b.sample(wi, us[2 * i], us[2 * i + 1], 550e-9);
      const double w = smp ? smp->weight : 0.0;
      s1 += w;
      s2 += w * w;
    }
    n += 4096;
    for (double& x : us) x = u(rng);  // fresh numbers for the variance (cheap next to sample)
  }
  const double mean = s1 / n, var = std::max(0.0, s2 / n - mean * mean);
  state.counters["samples/s"] = benchmark::Counter(n, benchmark::Counter::kIsRate);
  state.counters["albedo"] = mean;
  state.counters["weight_var"] = var;
  // 1 / (variance x seconds per sample): samples/s / variance (set after the run).
  state.counters["efficiency"] =
      benchmark::Counter(var > 0 ? n / var : 0.0, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_TabulatedBrdfSample)
    ->ArgsProduct({{0, 1}, {0, 45, 75, 85}})
    ->ArgNames({"visible", "theta"})
    ->Unit(benchmark::kMillisecond);

// Construction of the distribution (sigma+ grid and samplers) on 1025^2: 0 = ndf, 1 = visible.
void BM_TabulatedConstruct(benchmark::State& state) {
  const auto s = state.range(0) ? TabulatedSampling::Visible : TabulatedSampling::Ndf;
  std::size_t bytes = 0;
  for (auto _ : state) {
    auto d = make(s);
    bytes = d->sampling_memory_bytes();
    benchmark::DoNotOptimize(d);
  }
  state.counters["sampling_MB"] = static_cast<double>(bytes) / (1 << 20);
}
BENCHMARK(BM_TabulatedConstruct)
    ->Arg(0)
    ->Arg(1)
    ->ArgName("visible")
    ->Unit(benchmark::kMillisecond)
    ->Iterations(2);

}  // namespace
