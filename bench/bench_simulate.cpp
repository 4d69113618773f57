// Westin 1992 simulation throughput on the W92 Fig. 6 surface at W92's polygon count (512^2
// samples, 524 288 triangles, Gaussian sigma = 10 um, tau = 65 um, mirror facets):
//  - BareEmbree: rtcIntersect1 of random rays (uniform points of the tile, uniform downward
//    directions) against the same Embree scene, nothing else -- the reference;
//  - Tracer: the micro-scene tracer alone (tile wrap, scattering, bookkeeping), exits dropped;
//  - Simulate: the full estimator at l_max = 15 (exits projected on the SH basis, one outer
//    product per incident direction).
// Counters: Embree queries and exit rays per second of CPU time of the calling thread: run with
// OMP_NUM_THREADS=1 for per-core rates that a loaded machine does not distort (docs/benchmarks.md).
// The estimator runs its blocks on worker threads, so its rates (and BM_SimulateSummary's) are per
// second of CPU time of the whole process (getrusage, all threads); BM_SimulateSummary measures the
// bare loop and the estimator at 1 and 2 threads in one go and reports the ratios and the load.
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>
#include <omp.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <memory>

#include "bench_load.hpp"
#include "core/embree_ray.hpp"
#include "microbrdf/generate.hpp"
#include "microbrdf/simulate.hpp"
#include "microscene_test_util.hpp"

using namespace microbrdf;

namespace {

double process_cpu() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

double wall() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

const MicroScene& scene(bool grid) {
  static std::unique_ptr<MicroScene> s[2];
  if (!s[grid]) {
    s[grid] = std::make_unique<MicroScene>(test_util::gaussian_mirror_desc(
        512, 65e-6 / 8, 10e-6, 65e-6, GaussianSurfaceParams{}.seed, grid));
  }
  return *s[grid];
}

// `batch` bare rtcIntersect1 queries of random rays (round = seed); returns the hits.
std::uint64_t bare_rays(const MicroScene& sc, std::int64_t batch, std::uint64_t round) {
  auto* rs = static_cast<RTCScene>(sc.embree_scene());
  std::uint64_t h = 0;
#pragma omp parallel for schedule(static, 1024) reduction(+ : h)
  for (std::int64_t i = 0; i < batch; ++i) {
    SimRng rng(round, static_cast<std::uint64_t>(i));
    const Eigen::Vector3d u = uniform_hemisphere(rng.uniform(), rng.uniform());
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    const double ox = rng.uniform() * sc.width();  // (two statements: x drawn before y)
    const double oy = rng.uniform() * sc.height();
    detail::fill_rayhit(rh, Eigen::Vector3d(ox, oy, sc.zmax()), -u, 0, 1e30f);
    rtcIntersect1(rs, &ctx, &rh);
    h += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
  }
  return h;
}

void BM_SimulateBareEmbree(benchmark::State& state) {
  const MicroScene& sc = scene(state.range(0) != 0);
  const std::int64_t batch = 1 << 16;
  std::uint64_t hits = 0, round = 0;
  for (auto _ : state) {
    hits += bare_rays(sc, batch, round);
    ++round;
  }
  state.counters["queries/s"] =
      benchmark::Counter(double(batch), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["hit_fraction"] = double(hits) / double(batch * round);
  state.SetLabel(std::string(state.range(0) ? "grid" : "triangles") + ", 524288 triangles, " +
                 std::to_string(omp_get_max_threads()) + " threads");
}
BENCHMARK(BM_SimulateBareEmbree)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// The tracer alone (exits dropped): `dirs` incident directions of 16 points, seed `round`.
TraceCounters trace_only(const MicroScene& sc, std::int64_t dirs, std::uint64_t round) {
  const int points = 16;
  std::vector<TraceCounters> cnt(omp_get_max_threads());
#pragma omp parallel
  {
    MicroTracer t(sc, TraceOptions{});
    auto& c = cnt[omp_get_thread_num()];
#pragma omp for schedule(static, 16)
    for (std::int64_t k = 0; k < dirs; ++k) {
      SimRng rng(round, static_cast<std::uint64_t>(k));
      const Eigen::Vector3d u = uniform_hemisphere(rng.uniform(), rng.uniform());
      t.trace(
          u, points, rng, [](const Eigen::Vector3d&, double) {}, c);
    }
  }
  TraceCounters total;
  for (const auto& c : cnt) total.merge(c);
  return total;
}

void BM_SimulateTracer(benchmark::State& state) {
  const MicroScene& sc = scene(state.range(0) != 0);
  TraceCounters total;
  std::uint64_t round = 0;
  for (auto _ : state) total.merge(trace_only(sc, 4096, round++));
  state.counters["queries/s"] = benchmark::Counter(double(total.segments) / double(round),
                                                   benchmark::Counter::kIsIterationInvariantRate);
  state.counters["exits/s"] = benchmark::Counter(double(total.exits) / double(round),
                                                 benchmark::Counter::kIsIterationInvariantRate);
  state.counters["queries_per_ray"] = double(total.segments) / double(total.incident_rays);
  state.SetLabel(state.range(0) ? "grid" : "triangles");
}
BENCHMARK(BM_SimulateTracer)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_SimulateEstimator(benchmark::State& state) {
  const MicroScene& sc = scene(false);
  SimulateOptions o;
  o.lmax = static_cast<int>(state.range(0));
  o.incident_directions = 8192;
  o.points = 16;
  SimulateStats total;
  std::uint64_t round = 0;
  double cpu = 0;
  for (auto _ : state) {
    o.seed = ++round;
    SimulateStats st;
    const double c0 = process_cpu();
    benchmark::DoNotOptimize(simulate(sc, o, &st));
    cpu += process_cpu() - c0;
    total.counters.merge(st.counters);
  }
  state.counters["queries_per_cpu_s"] = double(total.counters.segments) / cpu;
  state.counters["exits_per_cpu_s"] = double(total.counters.exits) / cpu;
  state.SetLabel("lmax " + std::to_string(o.lmax) + ", 16 points per direction, process CPU");
}
BENCHMARK(BM_SimulateEstimator)->Arg(15)->Arg(8)->Unit(benchmark::kMillisecond);

// One run, interleaved: the bare loop and the estimator (lmax 15, 16 points) with 1 and 2 threads,
// each timed `reps` times. Rates per second of process CPU (all threads: what the work costs,
// independent of how much of the machine the process got) and per second of the best wall time.
void BM_SimulateSummary(benchmark::State& state) {
  const double load0 = microbrdf::bench::load_average();
  const MicroScene& sc = scene(false);
  const std::int64_t batch = 1 << 17;
  const int reps = 3;
  struct Rate {
    double cpu = 0, best_wall = 1e30, work = 0;
  };
  Rate bare[2], est[2], tracer[2];
  std::uint64_t seed = 0;
  for (auto _ : state) {
    for (int rep = 0; rep < reps; ++rep)
      for (int nt : {1, 2}) {
        const int before = omp_get_max_threads();
        omp_set_num_threads(nt);
        double c0 = process_cpu(), w0 = wall();
        benchmark::DoNotOptimize(bare_rays(sc, batch, ++seed));
        Rate& b = bare[nt - 1];
        b.cpu += process_cpu() - c0;
        b.best_wall = std::min(b.best_wall, wall() - w0);
        b.work += double(batch);
        c0 = process_cpu();
        w0 = wall();
        const TraceCounters tc = trace_only(sc, 4096, ++seed);
        Rate& tr = tracer[nt - 1];
        tr.cpu += process_cpu() - c0;
        tr.best_wall = std::min(tr.best_wall, wall() - w0);
        tr.work += double(tc.exits);
        omp_set_num_threads(before);
        SimulateOptions o;
        o.lmax = 15;
        o.points = 16;
        o.incident_directions = 8192;
        o.threads = nt;
        o.seed = ++seed;
        SimulateStats st;
        c0 = process_cpu();
        w0 = wall();
        benchmark::DoNotOptimize(simulate(sc, o, &st));
        Rate& e = est[nt - 1];
        e.cpu += process_cpu() - c0;
        e.best_wall = std::min(e.best_wall, wall() - w0);
        e.work += double(st.counters.exits);
      }
  }
  const double iters = double(state.iterations()) * reps;
  for (int i = 0; i < 2; ++i) {
    const std::string t = std::to_string(i + 1) + "t";
    state.counters["bare_rays_per_cpu_s_" + t] = bare[i].work / bare[i].cpu;
    state.counters["exits_per_cpu_s_" + t] = est[i].work / est[i].cpu;
    state.counters["ratio_cpu_" + t] = (est[i].work / est[i].cpu) / (bare[i].work / bare[i].cpu);
    state.counters["ratio_wall_" + t] =
        (est[i].work / iters / est[i].best_wall) / (bare[i].work / iters / bare[i].best_wall);
    // The tracer alone (no spherical harmonics): the ceiling of ratio_cpu.
    state.counters["tracer_ratio_cpu_" + t] =
        (tracer[i].work / tracer[i].cpu) / (bare[i].work / bare[i].cpu);
  }
  // CPU for the same estimator run with one thread over two (the goal: never above 1).
  state.counters["est_cpu_1t_over_2t"] = est[0].cpu / est[1].cpu;
  state.counters["load_before"] = load0;
  state.counters["load_after"] = microbrdf::bench::load_average();
  state.SetLabel("lmax 15, 16 points, 524288 triangles; rates per process CPU second");
}
BENCHMARK(BM_SimulateSummary)->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace
