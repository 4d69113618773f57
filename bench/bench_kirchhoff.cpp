// Kirchhoff distribution D_K of one 640 x 480 scan at 110 nm (stainless #4 brushed preset, Dong's
// scan size, 70.4 x 52.8 um) on the full 1025^2 table at lambda_q = 555 nm, side by side in one
// run with
//  - the direct-summation reference, timed on 64 random disk nodes and extrapolated to all
//    825,242 disk nodes (a full direct table takes hours);
//  - one zero-padded complex 2-D FFT of the same patch (exp(-i q_z h) padded to 1280 x 960), the
//    unit: FFTW itself with an FFTW_MEASURE plan made once (FFTW's threads, as many as OpenMP's),
//    including the fill (sincos per sample, zeros only where the padding is), on an
//    fftw_malloc'ed buffer. The project's own transform (FFTW_ESTIMATE plan, std::polar fill
//    of a zeroed array) is timed next to it, as a second, slower unit.
// BM_KirchhoffSummary reports the ratios (speed-up, cost in padded FFTs of either unit), the
// fast method's relative L1 error on those nodes and the load average as counters, for the
// midpoint rule (the default) and for the exact integration over the triangles, each against
// the direct sums of the same integral, and the midpoint rule's departure from the exact one.
// BM_KirchhoffMidpointSummary times the midpoint rule alone against the honest unit in
// interleaved rounds, in wall and in process CPU time.
#include <benchmark/benchmark.h>
#include <fftw3.h>
#include <omp.h>
#include <time.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <functional>
#include <random>

#include "bench_cpu.hpp"
#include "bench_load.hpp"
#include "core/fft.hpp"
#include "microbrdf/generate.hpp"
#include "microbrdf/kirchhoff.hpp"

using namespace microbrdf;

namespace {

constexpr double kLq = 555e-9;
constexpr std::size_t kN = 1025;

const Surface& scan() {
  static const Surface s = [] {
    BrushedParams b = brushed_preset("stainless4");
    b.nx = 640;
    b.ny = 480;
    return generate_brushed(b);
  }();
  return s;
}

const KirchhoffPatch& patch() {
  static const KirchhoffPatch p = make_kirchhoff_patch(scan());
  return p;
}

const std::vector<std::size_t>& nodes() {
  static const std::vector<std::size_t> v = [] {
    std::mt19937_64 rng(7);
    std::uniform_int_distribution<std::size_t> pick(0, kN * kN - 1);
    std::vector<std::size_t> out;
    while (out.size() < 64) {
      std::size_t k = pick(rng);
      if (kirchhoff_node_q(kN, k % kN, k / kN, kLq).z() > 0) out.push_back(k);
    }
    return out;
  }();
  return v;
}

std::size_t disk_nodes() {
  std::size_t n = 0;
  for (std::size_t i = 0; i < kN * kN; ++i)
    if (kirchhoff_node_q(kN, i % kN, i / kN, kLq).z() > 0) ++n;
  return n;
}

// One zero-padded complex 2-D FFT of exp(-i q_z h) of the patch.
struct PaddedFft {
  std::size_t mx, my;
  detail::Fft2c fft;
  PaddedFft()
      : mx(detail::fft_good_size(2 * scan().nx)),
        my(detail::fft_good_size(2 * scan().ny)),
        fft(mx, my) {}
  void run() {
    const auto& p = patch();
    auto& d = fft.data();
    std::fill(d.begin(), d.end(), std::complex<double>(0, 0));
    const double qz = 4 * M_PI / kLq;
    for (std::size_t y = 0; y < p.ny; ++y)
      for (std::size_t x = 0; x < p.nx; ++x)
        d[y * mx + x] = std::polar(p.w[y * p.nx + x], -qz * p.h[y * p.nx + x]);
    fft.execute();
  }
};

// The honest unit: FFTW_MEASURE plan, made once; the fill writes w exp(-i q_z h) and the zeros
// of the padding only.
struct MeasuredFft {
  std::size_t mx, my;
  fftw_complex* d = nullptr;
  fftw_plan plan = nullptr;
  MeasuredFft()
      : mx(detail::fft_good_size(2 * scan().nx)), my(detail::fft_good_size(2 * scan().ny)) {
    PaddedFft init;  // FFTW's threads are initialised by the project's first plan
    d = fftw_alloc_complex(mx * my);
    fftw_plan_with_nthreads(omp_get_max_threads());
    plan = fftw_plan_dft_2d(static_cast<int>(my), static_cast<int>(mx), d, d, FFTW_FORWARD,
                            FFTW_MEASURE);
  }
  ~MeasuredFft() {
    fftw_destroy_plan(plan);
    fftw_free(d);
  }
  MeasuredFft(const MeasuredFft&) = delete;
  MeasuredFft& operator=(const MeasuredFft&) = delete;
  void run() {
    const auto& p = patch();
    const double qz = 4 * M_PI / kLq;
    const long rows = static_cast<long>(my);
    for (long yy = 0; yy < rows; ++yy) {
      const auto y = static_cast<std::size_t>(yy);
      fftw_complex* row = d + y * mx;
      std::size_t x = 0;
      if (y < p.ny)
        for (; x < p.nx; ++x) {
          const double ph = -qz * p.h[y * p.nx + x], w = p.w[y * p.nx + x];
          row[x][0] = w * std::cos(ph);
          row[x][1] = w * std::sin(ph);
        }
      for (; x < mx; ++x) row[x][0] = row[x][1] = 0.0;
    }
    fftw_execute(plan);
  }
};

using microbrdf::bench::load_average;

void BM_KirchhoffFast(benchmark::State& state) {
  const auto& p = patch();
  double acc = std::pow(10.0, -static_cast<double>(state.range(0)));
  KirchhoffFastInfo info;
  const auto m = state.range(1) ? KirchhoffIntegration::Exact : KirchhoffIntegration::Midpoint;
  for (auto _ : state)
    benchmark::DoNotOptimize(kirchhoff_table_fast(p, kLq, kN, acc, &info, false, m));
  state.counters["terms"] = static_cast<double>(info.terms);
  state.counters["points"] = static_cast<double>(info.points_per_triangle);
}

void BM_KirchhoffDirect64Nodes(benchmark::State& state) {
  const auto& p = patch();
  for (auto _ : state) benchmark::DoNotOptimize(kirchhoff_nodes_direct(p, kLq, kN, nodes()));
}

void BM_PaddedFft2d(benchmark::State& state) {
  PaddedFft f;
  for (auto _ : state) f.run();
  state.counters["size"] = static_cast<double>(f.mx * f.my);
}

void BM_PaddedFft2dMeasured(benchmark::State& state) {
  MeasuredFft f;
  for (auto _ : state) f.run();
  state.counters["size"] = static_cast<double>(f.mx * f.my);
}

// One scan file's worth: patch preparation (slopes, window) + fast D_K + averaging.
void BM_KirchhoffScanToTable(benchmark::State& state) {
  KirchhoffOptions o;
  o.window = KirchhoffWindow::Hann;
  o.integration = state.range(0) ? KirchhoffIntegration::Exact : KirchhoffIntegration::Midpoint;
  for (auto _ : state) benchmark::DoNotOptimize(estimate_kirchhoff(scan(), o));
}

double seconds(const std::function<void()>& f, int reps) {
  auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < reps; ++i) f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / reps;
}

// Best wall time of `reps` calls (the least disturbed by the other processes).
double best_seconds(const std::function<void()>& f, int reps) {
  double best = 1e30;
  for (int i = 0; i < reps; ++i) best = std::min(best, seconds(f, 1));
  return best;
}

void BM_KirchhoffSummary(benchmark::State& state) {
  const double load0 = load_average();
  const auto& p = patch();
  PaddedFft f;
  MeasuredFft g;
  std::vector<double> fast, direct, exact, exact_direct;
  KirchhoffFastInfo info, info_exact;
  double t_fast = 0, t_direct = 0, t_fft = 0, t_own = 0, t_exact = 0, t_fft_after = 0;
  const auto ex = KirchhoffIntegration::Exact;
  for (auto _ : state) {
    t_fft = best_seconds([&] { g.run(); }, 20);
    t_own = best_seconds([&] { f.run(); }, 10);
    t_fast = best_seconds([&] { fast = kirchhoff_table_fast(p, kLq, kN, 1e-3, &info); }, 3);
    t_direct = seconds([&] { direct = kirchhoff_nodes_direct(p, kLq, kN, nodes()); }, 1);
    t_exact =
        seconds([&] { exact = kirchhoff_table_fast(p, kLq, kN, 1e-3, &info_exact, false, ex); }, 1);
    exact_direct = kirchhoff_nodes_direct(p, kLq, kN, nodes(), ex);
    t_fft_after = best_seconds([&] { g.run(); }, 20);  // the unit again, after the long runs
  }
  double num = 0, den = 0, num_x = 0, den_x = 0, num_mx = 0;
  for (std::size_t i = 0; i < nodes().size(); ++i) {
    num += std::fabs(fast[nodes()[i]] - direct[i]);
    den += std::fabs(direct[i]);
    num_x += std::fabs(exact[nodes()[i]] - exact_direct[i]);
    den_x += std::fabs(exact_direct[i]);
    num_mx += std::fabs(fast[nodes()[i]] - exact[nodes()[i]]);
  }
  state.counters["exact_s"] = t_exact;
  state.counters["exact_in_ffts"] = t_exact / std::max(t_fft, t_fft_after);
  state.counters["exact_over_midpoint"] = t_exact / t_fast;
  state.counters["exact_points"] = static_cast<double>(info_exact.points_per_triangle);
  state.counters["rel_L1_exact"] = num_x / den_x;
  state.counters["midpoint_vs_exact_L1"] = num_mx / den_x;
  state.counters["fft_after_ms"] = 1e3 * t_fft_after;
  const double t_direct_full =
      t_direct / static_cast<double>(nodes().size()) * static_cast<double>(disk_nodes());
  state.counters["fast_s"] = t_fast;
  state.counters["fft_ms"] = 1e3 * t_fft;
  state.counters["own_fft_ms"] = 1e3 * t_own;
  state.counters["fast_in_own_ffts"] = t_fast / t_own;
  state.counters["load_before"] = load0;
  state.counters["load_after"] = load_average();
  state.counters["direct_full_s"] = t_direct_full;
  state.counters["speedup"] = t_direct_full / t_fast;
  state.counters["fast_in_ffts"] = t_fast / t_fft;
  state.counters["rel_L1"] = num / den;
  state.counters["terms"] = static_cast<double>(info.terms);
}

// The midpoint rule alone (the default integration), quick enough to repeat: rounds of four
// honest units then one fast table, interleaved so that both see the same load; the ratio is the
// best table over the best unit (the least flattering pairing), with rel_L1 against the direct
// sums on the 64 random disk nodes. The same ratio in process CPU time (all threads; a loaded
// machine inflates wall times, and FFTW's threads wait for each other more than the table's
// helpers do) is reported next to it.
using microbrdf::bench::process_cpu;  // (bench_cpu.hpp: all threads)

void BM_KirchhoffMidpointSummary(benchmark::State& state) {
  const double load0 = load_average();
  const auto& p = patch();
  MeasuredFft g;
  std::vector<double> fast, direct;
  KirchhoffFastInfo info;
  double t_fft = 1e30, t_fast = 1e30, c_fft = 1e30, c_fast = 1e30;
  auto unit = [&] {
    for (int i = 0; i < 4; ++i) {
      const double c0 = process_cpu();
      t_fft = std::min(t_fft, seconds([&] { g.run(); }, 1));
      c_fft = std::min(c_fft, process_cpu() - c0);
    }
  };
  const int rounds = static_cast<int>(state.range(0));
  for (auto _ : state) {
    for (int r = 0; r < rounds; ++r) {
      unit();
      const double c0 = process_cpu();
      t_fast = std::min(t_fast,
                        seconds([&] { fast = kirchhoff_table_fast(p, kLq, kN, 1e-3, &info); }, 1));
      c_fast = std::min(c_fast, process_cpu() - c0);
    }
    unit();
    direct = kirchhoff_nodes_direct(p, kLq, kN, nodes());
  }
  double num = 0, den = 0;
  for (std::size_t i = 0; i < nodes().size(); ++i) {
    num += std::fabs(fast[nodes()[i]] - direct[i]);
    den += std::fabs(direct[i]);
  }
  state.counters["fast_s"] = t_fast;
  state.counters["fft_ms"] = 1e3 * t_fft;
  state.counters["fast_in_ffts"] = t_fast / t_fft;
  state.counters["fast_cpu_s"] = c_fast;
  state.counters["fft_cpu_ms"] = 1e3 * c_fft;
  state.counters["fast_in_ffts_cpu"] = c_fast / c_fft;
  state.counters["threads"] = omp_get_max_threads();
  state.counters["rel_L1"] = num / den;
  state.counters["terms"] = static_cast<double>(info.terms);
  state.counters["load_before"] = load0;
  state.counters["load_after"] = load_average();
}

// The default stack over lambda_q (ndf --dk-stack visible: 13 tables for 555 nm) against one
// table, both through KirchhoffAccumulator on the same scan, between honest units (rounds as
// above, best of each): what the stack adds to a D_K run, in honest FFT units and as a ratio.
void BM_KirchhoffStack(benchmark::State& state) {
  const double load0 = load_average();
  MeasuredFft g;
  KirchhoffOptions one;
  one.resolution = kN;
  one.wavelength_q = kLq;
  KirchhoffOptions stack = one;
  stack.stack_wavelengths_q = kirchhoff_stack_layers("visible", kLq);
  double t_fft = 1e30, t_one = 1e30, t_stack = 1e30;
  auto unit = [&] {
    for (int i = 0; i < 4; ++i) t_fft = std::min(t_fft, seconds([&] { g.run(); }, 1));
  };
  for (auto _ : state) {
    for (int r = 0; r < 2; ++r) {
      unit();
      t_one =
          std::min(t_one, seconds([&] { (void)KirchhoffAccumulator(one).estimate(scan()); }, 1));
      unit();
      t_stack = std::min(t_stack,
                         seconds([&] { (void)KirchhoffAccumulator(stack).estimate(scan()); }, 1));
    }
    unit();
  }
  state.counters["tables"] = static_cast<double>(stack.stack_wavelengths_q.size() + 1);
  state.counters["one_s"] = t_one;
  state.counters["stack_s"] = t_stack;
  state.counters["fft_ms"] = 1e3 * t_fft;
  state.counters["one_in_ffts"] = t_one / t_fft;
  state.counters["stack_in_ffts"] = t_stack / t_fft;
  state.counters["stack_over_one"] = t_stack / t_one;
  state.counters["load_before"] = load0;
  state.counters["load_after"] = load_average();
}

}  // namespace

BENCHMARK(BM_PaddedFft2d)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PaddedFft2dMeasured)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_KirchhoffFast)
    ->Args({2, 0})
    ->Args({3, 0})
    ->Args({6, 0})
    ->Args({3, 1})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);
BENCHMARK(BM_KirchhoffDirect64Nodes)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_KirchhoffScanToTable)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_KirchhoffMidpointSummary)->Arg(8)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_KirchhoffSummary)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_KirchhoffStack)->Unit(benchmark::kSecond)->Iterations(1);
