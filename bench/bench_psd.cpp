// The areal PSD (include/microbrdf/psd.hpp) of one 1025 x 1025 scan (a generated Gaussian
// surface, sigma 5 nm, tau 5 um, 250 nm spacing) against the honest unit of the same run: one
// bare real-to-complex 2-D FFT of the same size by FFTW itself, FFTW_MEASURE plan made once on
// fftw_malloc'ed buffers, FFTW's threads as many as OpenMP's, the copy of the heights into its
// input included. The PSD adds: the mean and Sq, the Hann weights, the windowed copy, the
// project's FFT (FFTW_ESTIMATE plan made per call) and the Hermitian unfolding onto the centred
// two-sided grid. BM_PsdSummary times both in interleaved rounds and reports the ratio.
#include <benchmark/benchmark.h>
#include <fftw3.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <functional>

#include "bench_load.hpp"
#include "core/fft.hpp"
#include "microbrdf/generate.hpp"
#include "microbrdf/psd.hpp"

using namespace microbrdf;

namespace {

constexpr std::size_t kN = 1025;

const Surface& scan() {
  static const Surface s = [] {
    GaussianSurfaceParams p;
    p.nx = p.ny = kN;
    p.dx = p.dy = 250e-9;
    p.sigma = 5e-9;
    p.tau_x = p.tau_y = 5e-6;
    p.seed = 101;
    return generate_gaussian(p);
  }();
  return s;
}

struct MeasuredR2c {
  double* in = nullptr;
  fftw_complex* out = nullptr;
  fftw_plan plan = nullptr;
  MeasuredR2c() {
    // FFTW's threads are set up by the project's planner lock (once per process).
    const auto lock = detail::fftw_planner_lock();
    in = fftw_alloc_real(kN * kN);
    out = fftw_alloc_complex(kN * (kN / 2 + 1));
    fftw_plan_with_nthreads(omp_get_max_threads());
    plan = fftw_plan_dft_r2c_2d(static_cast<int>(kN), static_cast<int>(kN), in, out, FFTW_MEASURE);
  }
  ~MeasuredR2c() {
    const auto lock = detail::fftw_planner_lock();
    fftw_destroy_plan(plan);
    fftw_free(in);
    fftw_free(out);
  }
  MeasuredR2c(const MeasuredR2c&) = delete;
  MeasuredR2c& operator=(const MeasuredR2c&) = delete;
  void run() {
    std::memcpy(in, scan().z.data(), kN * kN * sizeof(double));
    fftw_execute(plan);
  }
};

MeasuredR2c& unit() {
  static MeasuredR2c u;
  return u;
}

double seconds(const std::function<void()>& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void BM_Psd1025(benchmark::State& state) {
  scan();
  for (auto _ : state) benchmark::DoNotOptimize(areal_psd(scan()).value.data());
}

void BM_FftwMeasureR2c1025(benchmark::State& state) {
  scan();
  auto& u = unit();
  for (auto _ : state) {
    u.run();
    benchmark::DoNotOptimize(u.out);
  }
}

// Interleaved rounds (best of each), so both see the same machine load.
void BM_PsdSummary(benchmark::State& state) {
  scan();
  auto& u = unit();
  const double load0 = microbrdf::bench::load_average();
  double best_psd = 1e30, best_fft = 1e30;
  for (auto _ : state)
    for (int r = 0; r < 10; ++r) {
      best_fft = std::min(best_fft, seconds([&] { u.run(); }));
      best_psd = std::min(best_psd, seconds([&] { benchmark::DoNotOptimize(areal_psd(scan())); }));
    }
  state.counters["psd_ms"] = 1e3 * best_psd;
  state.counters["fft_ms"] = 1e3 * best_fft;
  state.counters["psd_in_ffts"] = best_psd / best_fft;
  state.counters["threads"] = omp_get_max_threads();
  state.counters["load_before"] = load0;
  state.counters["load_after"] = microbrdf::bench::load_average();
}

}  // namespace

BENCHMARK(BM_Psd1025)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FftwMeasureR2c1025)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PsdSummary)->Unit(benchmark::kMillisecond)->Iterations(1);
