// The C++ side of the Python binding's overhead benchmark (bench/python_eval_overhead.py):
// BRDF evaluations over 10^6 direction pairs stored as numpy stores an (N, 3) float64 array,
// in the loop the binding runs (Brdf::eval per pair, one thread). Both sides build the same
// pairs (spherical Fibonacci points, wo_i = point (7919 i mod N)) and the same BRDF (GGX
// alpha 0.1 x 0.3, n = 1.2, k = 3.5), so the ratio of their times is the binding's overhead.
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "microbrdf/fresnel.hpp"
#include "microbrdf/microfacet.hpp"
#include "microbrdf/microfacet_brdf.hpp"

using namespace microbrdf;

namespace {

constexpr std::size_t kPairs = 1000000;

// Point i of N on the upper hemisphere (spherical Fibonacci: equal-area rings in cos theta).
void fibonacci_direction(std::size_t i, std::size_t n, double* out) {
  const double golden = 2.399963229728653;  // pi (3 - sqrt 5)
  const double z = 1 - (static_cast<double>(i) + 0.5) / static_cast<double>(n);
  const double r = std::sqrt(1 - z * z), phi = golden * static_cast<double>(i);
  out[0] = r * std::cos(phi);
  out[1] = r * std::sin(phi);
  out[2] = z;
}

void BM_BrdfEvalLoop(benchmark::State& state) {
  const MicrofacetBrdf brdf(std::make_shared<GgxDistribution>(0.1, 0.3),
                            std::make_shared<ConductorFresnel>(constant_index(1.2, 3.5)));
  std::vector<double> wi(3 * kPairs), wo(3 * kPairs), f(kPairs);
  for (std::size_t i = 0; i < kPairs; ++i) {
    fibonacci_direction(i, kPairs, &wi[3 * i]);
    fibonacci_direction((7919 * i) % kPairs, kPairs, &wo[3 * i]);
  }
  for (auto _ : state) {
    for (std::size_t i = 0; i < kPairs; ++i) {
      const double* a = &wi[3 * i];
      const double* b = &wo[3 * i];
      f[i] = brdf.eval(Vec3(a[0], a[1], a[2]), Vec3(b[0], b[1], b[2]), 555e-9);
    }
    benchmark::DoNotOptimize(f.data());
    benchmark::ClobberMemory();
  }
  state.counters["pairs/s"] = benchmark::Counter(static_cast<double>(kPairs),
                                                 benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_BrdfEvalLoop)->Unit(benchmark::kMillisecond);

}  // namespace
