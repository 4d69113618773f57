// Multiple scattering (microfacet random walk): eval and sample per call against the
// single-scattering MicrofacetBrdf on the same distribution, and the cost and size of the
// deterministic lobe table (docs/benchmarks.md, docs/multiple_scattering.md).
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "microbrdf/fresnel.hpp"
#include "microbrdf/microfacet.hpp"
#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/multiple_scattering.hpp"
#include "microbrdf/tabulated_distribution.hpp"

using namespace microbrdf;

namespace {

constexpr std::size_t kBatch = 1024;

std::vector<Vec3> directions(unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3> v(kBatch);
  for (auto& d : v) {
    const double ct = u(rng), st = std::sqrt(1 - ct * ct), p = 6.283185307179586 * u(rng);
    d = Vec3(st * std::cos(p), st * std::sin(p), ct);
  }
  return v;
}

// 0 beckmann, 1 ggx, 2 ellipsoid (all 0.3 x 0.6), 3 the Beckmann lobe tabulated on 513^2.
std::shared_ptr<const MicrofacetDistribution> ndf(int which) {
  switch (which) {
    case 0:
      return make_distribution(NdfSpec{"beckmann", 0.3, 0.6, 0.3, 0, 0, 0, {}});
    case 1:
      return make_distribution(NdfSpec{"ggx", 0.3, 0.6, 0.3, 0, 0, 0, {}});
    case 2:
      return make_distribution(NdfSpec{"ellipsoid", 0.3, 0.6, 0, 0, 0, 0.3, {}});
    default: {
      static const auto t = std::make_shared<TabulatedDistribution>(tabulate(
          *make_distribution(NdfSpec{"beckmann", 0.3, 0.6, 0.3, 0, 0, 0, {}}), "beckmann", 513));
      return t;
    }
  }
}
const char* kNames[] = {"beckmann 0.3x0.6", "ggx 0.3x0.6", "ellipsoid 0.3x0.6",
                        "tabulated beckmann 513^2"};

std::shared_ptr<const Fresnel> copper() { return std::make_shared<ConductorFresnel>(metal("Cu")); }

// One BRDF per distribution, built once (the table takes a second or two for anisotropic NDFs).
const MultipleScatteringBrdf& ms_brdf(int which, int walks) {
  static std::shared_ptr<const MultipleScatteringBrdf> cache[4][3];
  const int slot = walks == 1 ? 0 : walks == 4 ? 1 : 2;
  auto& b = cache[which][slot];
  if (!b) {
    MultipleScatteringOptions o;
    o.eval_walks = walks;
    b = std::make_shared<MultipleScatteringBrdf>(ndf(which), copper(), o);
  }
  return *b;
}

void per_call(benchmark::State& state) {
  state.counters["ns/call"] = benchmark::Counter(
      static_cast<double>(kBatch),
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_SingleEval(benchmark::State& state) {
  const MicrofacetBrdf b(ndf(static_cast<int>(state.range(0))), copper());
  const auto wi = directions(1), wo = directions(2);
  for (auto _ : state) {
    double s = 0;
    for (std::size_t k = 0; k < kBatch; ++k) s += b.eval(wi[k], wo[k], 550e-9);
    benchmark::DoNotOptimize(s);
  }
  per_call(state);
  state.SetLabel(kNames[state.range(0)]);
}

// range(1): walks per eval (1, 4 = the renderer's, 64 = the default elsewhere).
void BM_MultipleEval(benchmark::State& state) {
  const auto& b = ms_brdf(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  const auto wi = directions(1), wo = directions(2);
  for (auto _ : state) {
    double s = 0;
    for (std::size_t k = 0; k < kBatch; ++k) s += b.eval(wi[k], wo[k], 550e-9);
    benchmark::DoNotOptimize(s);
  }
  per_call(state);
  state.SetLabel(std::string(kNames[state.range(0)]) + ", " + std::to_string(state.range(1)) +
                 " walks");
}

void BM_SingleSample(benchmark::State& state) {
  const MicrofacetBrdf b(ndf(static_cast<int>(state.range(0))), copper());
  const auto wi = directions(3), u = directions(4);
  for (auto _ : state) {
    double s = 0;
    for (std::size_t k = 0; k < kBatch; ++k)
      if (const auto r = b.sample(wi[k], 0.5 * (u[k].x() + 1), 0.5 * (u[k].y() + 1), 550e-9))
        s += r->weight;
    benchmark::DoNotOptimize(s);
  }
  per_call(state);
  state.SetLabel(kNames[state.range(0)]);
}

// One walk plus pdf() (the table look-up) per call.
void BM_MultipleSample(benchmark::State& state) {
  const auto& b = ms_brdf(static_cast<int>(state.range(0)), 4);
  const auto wi = directions(3), u = directions(4);
  for (auto _ : state) {
    double s = 0;
    for (std::size_t k = 0; k < kBatch; ++k)
      if (const auto r = b.sample(wi[k], 0.5 * (u[k].x() + 1), 0.5 * (u[k].y() + 1), 550e-9))
        s += r->weight;
    benchmark::DoNotOptimize(s);
  }
  per_call(state);
  state.SetLabel(kNames[state.range(0)]);
}

void BM_MultiplePdf(benchmark::State& state) {
  const auto& b = ms_brdf(static_cast<int>(state.range(0)), 4);
  const auto wi = directions(1), wo = directions(2);
  for (auto _ : state) {
    double s = 0;
    for (std::size_t k = 0; k < kBatch; ++k) s += b.pdf(wi[k], wo[k]);
    benchmark::DoNotOptimize(s);
  }
  per_call(state);
  state.SetLabel(kNames[state.range(0)]);
}

// The default table (12 x 24 nodes per direction, 256 walks with next-event estimation to
// every node and 4096 energy walks per incidence node), one thread; isotropic NDFs need one
// incidence azimuth (range(1) = 1: isotropic alpha 0.45).
void BM_Tabulate(benchmark::State& state) {
  const int which = static_cast<int>(state.range(0));
  const bool iso = state.range(1) == 1;
  std::shared_ptr<const MicrofacetDistribution> d =
      iso ? (which == 0 ? make_distribution(NdfSpec{"beckmann", 0.45, 0.45, 0, 0, 0, 0, {}})
                        : make_distribution(NdfSpec{"ggx", 0.45, 0.45, 0, 0, 0, 0, {}}))
          : ndf(which);
  const MicrofacetRandomWalk walk(d);
  MsTableOptions o;
  o.threads = 1;
  std::size_t bytes = 0;
  for (auto _ : state) {
    const MsTable t = tabulate_multiple_scattering(walk, nullptr, 550e-9, o);
    bytes = t.memory_bytes();
    benchmark::DoNotOptimize(t.node(0, 0));
  }
  state.counters["table_bytes"] = static_cast<double>(bytes);
  state.SetLabel(iso ? std::string(which == 0 ? "beckmann" : "ggx") + " 0.45 isotropic"
                     : kNames[which]);
}

}  // namespace

BENCHMARK(BM_SingleEval)->DenseRange(0, 3);
BENCHMARK(BM_MultipleEval)->ArgsProduct({{0, 1, 2, 3}, {1, 4, 64}});
BENCHMARK(BM_SingleSample)->DenseRange(0, 3);
BENCHMARK(BM_MultipleSample)->DenseRange(0, 3);
BENCHMARK(BM_MultiplePdf)->DenseRange(0, 3);
BENCHMARK(BM_Tabulate)
    ->Args({0, 1})
    ->Args({1, 1})
    ->Args({0, 0})
    ->Args({1, 0})
    ->Args({3, 0})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);
