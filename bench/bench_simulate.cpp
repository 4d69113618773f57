// Westin 1992 simulation throughput on the W92 Fig. 6 surface at W92's polygon count (512^2
// samples, 524 288 triangles, Gaussian sigma = 10 um, tau = 65 um, mirror facets):
//  - BareEmbree: rtcIntersect1 of random rays (uniform points of the tile, uniform downward
//    directions) against the same Embree scene, nothing else -- the reference;
//  - Tracer: the micro-scene tracer alone (tile wrap, scattering, bookkeeping), exits dropped;
//  - Simulate: the full estimator at l_max = 15 (exits projected on the SH basis, one outer
//    product per incident direction).
// Counters: Embree queries and exit rays per second of CPU time of the calling thread: run with
// OMP_NUM_THREADS=1 for per-core rates that a loaded machine does not distort (docs/benchmarks.md).
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>
#include <omp.h>

#include <memory>

#include "core/embree_ray.hpp"
#include "microbrdf/generate.hpp"
#include "microbrdf/simulate.hpp"
#include "microscene_test_util.hpp"

using namespace microbrdf;

namespace {

const MicroScene& scene(bool grid) {
  static std::unique_ptr<MicroScene> s[2];
  if (!s[grid]) {
    s[grid] = std::make_unique<MicroScene>(test_util::gaussian_mirror_desc(
        512, 65e-6 / 8, 10e-6, 65e-6, GaussianSurfaceParams{}.seed, grid));
  }
  return *s[grid];
}

void BM_SimulateBareEmbree(benchmark::State& state) {
  const MicroScene& sc = scene(state.range(0) != 0);
  auto* rs = static_cast<RTCScene>(sc.embree_scene());
  const std::int64_t batch = 1 << 16;
  std::uint64_t hits = 0, round = 0;
  for (auto _ : state) {
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
    hits += h;
    ++round;
  }
  state.counters["queries/s"] =
      benchmark::Counter(double(batch), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["hit_fraction"] = double(hits) / double(batch * round);
  state.SetLabel(std::string(state.range(0) ? "grid" : "triangles") + ", 524288 triangles, " +
                 std::to_string(omp_get_max_threads()) + " threads");
}
BENCHMARK(BM_SimulateBareEmbree)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_SimulateTracer(benchmark::State& state) {
  const MicroScene& sc = scene(state.range(0) != 0);
  const std::int64_t dirs = 4096;
  const int points = 16;
  TraceCounters total;
  std::uint64_t round = 0;
  for (auto _ : state) {
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
    for (const auto& c : cnt) total.merge(c);
    ++round;
  }
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
  for (auto _ : state) {
    o.seed = ++round;
    SimulateStats st;
    benchmark::DoNotOptimize(simulate(sc, o, &st));
    total.counters.merge(st.counters);
  }
  state.counters["queries/s"] = benchmark::Counter(double(total.counters.segments) / double(round),
                                                   benchmark::Counter::kIsIterationInvariantRate);
  state.counters["exits/s"] = benchmark::Counter(double(total.counters.exits) / double(round),
                                                 benchmark::Counter::kIsIterationInvariantRate);
  state.SetLabel("lmax " + std::to_string(o.lmax) + ", 16 points per direction");
}
BENCHMARK(BM_SimulateEstimator)->Arg(15)->Arg(8)->Unit(benchmark::kMillisecond);

}  // namespace
