// Geometric NDF estimation on a 640 x 480 scan at 110 nm (Dong's scan size), filter sigma 1 um:
// the separable masked-moment estimator next to the brute-force weighted least-squares fit per
// point (the reference in the library) in the same run, and the naive triangle histogram.
#include <benchmark/benchmark.h>

#include "microbrdf/generate.hpp"
#include "microbrdf/ndf_estimate.hpp"

using namespace microbrdf;

namespace {

const Surface& scan() {
  static const Surface s = [] {
    GaussianSurfaceParams p;
    p.nx = 640;
    p.ny = 480;
    p.dx = p.dy = 110e-9;
    p.sigma = 0.1e-6;
    p.tau_x = p.tau_y = 1e-6;
    Surface g = generate_gaussian(p);
    for (std::size_t i = 0; i < g.size(); i += 37)
      g.invalidate(i);  // a few holes, as real scans have
    return g;
  }();
  return s;
}

void BM_FilteredNormalsSeparable(benchmark::State& state) {
  const Surface& s = scan();
  for (auto _ : state) benchmark::DoNotOptimize(filtered_normals(s, 1e-6, 4.0, 0.5));
  state.counters["points/s"] = benchmark::Counter(static_cast<double>(s.size()),
                                                  benchmark::Counter::kIsIterationInvariantRate);
}

// Brute force on every 16th row (a full pass takes ~16x this); points/s is comparable.
void BM_FilteredNormalsBruteForce(benchmark::State& state) {
  const Surface& s = scan();
  std::size_t points = 0;
  for (auto _ : state) {
    points = 0;
    for (std::size_t iy = 0; iy < s.ny; iy += 16)
      for (std::size_t ix = 0; ix < s.nx; ++ix) {
        double m[3];
        benchmark::DoNotOptimize(filtered_normal_direct(s, ix, iy, 1e-6, 4.0, 0.5, m));
        ++points;
      }
  }
  state.counters["points/s"] = benchmark::Counter(static_cast<double>(points),
                                                  benchmark::Counter::kIsIterationInvariantRate);
}

void BM_NdfFiltered1025(benchmark::State& state) {
  NdfEstimateOptions o;
  o.filter_sigma_m = 1e-6;
  for (auto _ : state) benchmark::DoNotOptimize(estimate_ndf(scan(), o));
  state.counters["points/s"] = benchmark::Counter(static_cast<double>(scan().size()),
                                                  benchmark::Counter::kIsIterationInvariantRate);
}

void BM_NdfNaive1025(benchmark::State& state) {
  NdfEstimateOptions o;
  o.method = NdfMethod::Naive;
  for (auto _ : state) benchmark::DoNotOptimize(estimate_ndf(scan(), o));
  state.counters["triangles/s"] = benchmark::Counter(2.0 * static_cast<double>(scan().size()),
                                                     benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

BENCHMARK(BM_FilteredNormalsSeparable)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FilteredNormalsBruteForce)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NdfFiltered1025)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NdfNaive1025)->Unit(benchmark::kMillisecond);
