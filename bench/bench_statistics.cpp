// `info` statistics on a 640 x 480 scan (the MetroPro fixture's size): the whole compute_stats
// (moments, slopes, FFT ACF, correlation lengths), next to brute-force references in the same
// run: the axis-lag ACF summed directly (what corr_length_x/y need), and the full ACF by FFT vs
// directly on a small patch.
#include <benchmark/benchmark.h>

#include "bench_load.hpp"
#include "microbrdf/generate.hpp"
#include "microbrdf/io.hpp"
#include "microbrdf/level.hpp"
#include "microbrdf/statistics.hpp"

using namespace microbrdf;

namespace {

Surface scan(std::size_t nx, std::size_t ny) {
  GaussianSurfaceParams p;
  p.nx = nx;
  p.ny = ny;
  p.tau_x = p.tau_y = 10 * p.dx;
  return generate_gaussian(p);
}

void BM_InfoStats640x480(benchmark::State& state) {
  Surface s = scan(640, 480);
  for (auto _ : state) benchmark::DoNotOptimize(compute_stats(s));
  state.counters["points/s"] = benchmark::Counter(static_cast<double>(s.size()),
                                                  benchmark::Counter::kIsIterationInvariantRate);
}

void BM_InfoRealMetropro(benchmark::State& state) {
  Surface s;
  try {
    s = read_surface(std::string(MICROBRDF_TEST_DATA) + "/metropro-1.dat");
  } catch (...) {
    state.SkipWithError("metropro-1.dat unreadable");
    return;
  }
  for (auto _ : state) {
    Surface t = s;
    level_surface(t, LevelingSpec::parse("plane"));
    benchmark::DoNotOptimize(compute_stats(t));
  }
  state.counters["points/s"] = benchmark::Counter(static_cast<double>(s.size()),
                                                  benchmark::Counter::kIsIterationInvariantRate);
}

// Brute force: the x- and y-axis lags of the ACF summed directly (O(N * (nx + ny))).
void BM_AxisAcfDirect640x480(benchmark::State& state) {
  Surface s = scan(640, 480);
  for (auto _ : state) {
    double acc = 0;
    for (long l = 0; l < static_cast<long>(s.nx); ++l) acc += autocorrelation_direct(s, l, 0);
    for (long l = 0; l < static_cast<long>(s.ny); ++l) acc += autocorrelation_direct(s, 0, l);
    benchmark::DoNotOptimize(acc);
  }
}

void BM_FullAcfFft(benchmark::State& state) {
  Surface s =
      scan(static_cast<std::size_t>(state.range(0)), static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(autocorrelation(s));
  state.counters["lags/s"] =
      benchmark::Counter(static_cast<double>((2 * s.nx - 1) * (2 * s.ny - 1)),
                         benchmark::Counter::kIsIterationInvariantRate);
}

void BM_FullAcfDirect(benchmark::State& state) {
  Surface s =
      scan(static_cast<std::size_t>(state.range(0)), static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) {
    double acc = 0;
    for (long ly = -static_cast<long>(s.ny) + 1; ly < static_cast<long>(s.ny); ++ly)
      for (long lx = -static_cast<long>(s.nx) + 1; lx < static_cast<long>(s.nx); ++lx)
        acc += autocorrelation_direct(s, lx, ly);
    benchmark::DoNotOptimize(acc);
  }
  state.counters["lags/s"] =
      benchmark::Counter(static_cast<double>((2 * s.nx - 1) * (2 * s.ny - 1)),
                         benchmark::Counter::kIsIterationInvariantRate);
}

// Levelling a 1280 x 960 scan with holes (every 37th sample): the normal equations from row
// sums and the subtraction, on the helper threads (state.range(0) = polynomial degree).
Surface holed_scan() {
  Surface s = scan(1280, 960);
  for (std::size_t i = 0; i < s.size(); i += 37) s.invalidate(i);
  return s;
}

void BM_Level1280x960(benchmark::State& state) {
  const Surface s = holed_scan();
  Surface t = s;
  const int degree = static_cast<int>(state.range(0));
  const LevelingSpec spec{degree == 1 ? Leveling::Plane : Leveling::Polynomial, degree};
  for (auto _ : state) {
    state.PauseTiming();
    t.z = s.z;  // the same heights each time (levelling works in place)
    state.ResumeTiming();
    benchmark::DoNotOptimize(level_surface(t, spec));
  }
  state.counters["points/s"] = benchmark::Counter(static_cast<double>(s.size()),
                                                  benchmark::Counter::kIsIterationInvariantRate);
  state.counters["load"] = bench::load_average();
}

// Yardstick: what levelling must at least do, read every height and its mask flag twice (the
// sums, then the subtraction) and write the heights once, as plain loops on the same threads.
void BM_LevelStreamingPass1280x960(benchmark::State& state) {
  const Surface s = holed_scan();
  Surface t = s;
  for (auto _ : state) {
    state.PauseTiming();
    t.z = s.z;
    state.ResumeTiming();
    const long n = static_cast<long>(t.size());
    double sum = 0;
#pragma omp parallel for reduction(+ : sum)
    for (long i = 0; i < n; ++i)
      if (t.valid[static_cast<std::size_t>(i)]) sum += t.z[static_cast<std::size_t>(i)];
    const double mean = sum / static_cast<double>(n);
#pragma omp parallel for
    for (long i = 0; i < n; ++i)
      if (t.valid[static_cast<std::size_t>(i)]) t.z[static_cast<std::size_t>(i)] -= mean;
    benchmark::DoNotOptimize(t.z.data());
  }
  state.counters["points/s"] = benchmark::Counter(static_cast<double>(s.size()),
                                                  benchmark::Counter::kIsIterationInvariantRate);
  state.counters["load"] = bench::load_average();
}

}  // namespace

BENCHMARK(BM_Level1280x960)->Arg(1)->Arg(3)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_LevelStreamingPass1280x960)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_InfoStats640x480)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_InfoRealMetropro)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AxisAcfDirect640x480)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FullAcfFft)->Arg(64)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FullAcfDirect)->Arg(64)->Unit(benchmark::kMillisecond);
