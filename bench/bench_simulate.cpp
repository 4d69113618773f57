// Westin 1992 simulation throughput on the W92 Fig. 6 surface at W92's polygon count (512^2
// samples, 524 288 triangles, Gaussian sigma = 10 um, tau = 65 um, mirror facets):
//  - Replay: the yardstick. Every ray of the simulation's own paths (incident rays, bounces,
//    tile continuations and the escape rays, including those the tracer decides without Embree),
//    recorded once with their clipped tfar and replayed with bare rtcIntersect1 in the order the
//    tracer made them, nothing else;
//  - BareEmbree: the older yardstick, rtcIntersect1 of random rays (uniform points of the tile,
//    uniform downward directions, tfar = infinity) against the same scene;
//  - Tracer: the micro-scene tracer alone (tile wrap, scattering, bookkeeping), exits dropped;
//  - Estimator: the full estimator (exits projected on the SH basis, one outer product per
//    incident direction).
// BM_SimulateSummary is the acceptance figure: in one run, interleaved, with 1 and 2 threads, the
// replay of the rays of exactly the estimator's paths, the tracer on the same paths and the
// estimator itself (lmax 15, 16 points), rates per second of CPU time of the whole process
// (getrusage, all threads), the load average before and after; and the CPU of one thread over
// two for the estimator, the bare replay and two machine loops (compute, DRAM pointer chase).
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>
#include <omp.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <memory>
#include <vector>

#include "bench_cpu.hpp"
#include "bench_load.hpp"
#include "core/embree_ray.hpp"
#include "microbrdf/generate.hpp"
#include "microbrdf/simulate.hpp"
#include "microscene_test_util.hpp"

using namespace microbrdf;

namespace {

using microbrdf::bench::process_cpu;

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

constexpr int kPoints = 16;

// Incident direction `idx` of simulate() with `seed` (default options: stratified rounds of
// 1024 on a 32 x 32 grid); `rng` is left where simulate() hands it to the tracer.
Eigen::Vector3d direction(std::uint64_t seed, std::uint64_t idx, SimRng& rng) {
  rng = SimRng(seed, idx);
  double u1 = rng.uniform(), u2 = rng.uniform();
  const std::uint64_t k = idx % 1024;
  u1 = (double(k % 32) + u1) / 32.0;
  u2 = (double(k / 32) + u2) / 32.0;
  return uniform_hemisphere(u1, u2);
}

// The rays of the estimator's paths for `dirs` directions (a multiple of 1024) and `seed`, in
// the order the tracer makes them, each Embree query with its clipped tfar and the escape rays
// the tracer decides without a query as the queries they replace; `c` gets the counters.
std::vector<MicroRay> record_rays(const MicroScene& sc, std::int64_t dirs, std::uint64_t seed,
                                  TraceCounters& c) {
  std::vector<MicroRay> log;
  MicroTracer t(sc, TraceOptions{});
  t.log_rays(&log);
  for (std::int64_t k = 0; k < dirs; ++k) {
    SimRng rng(0);
    const Eigen::Vector3d u = direction(seed, std::uint64_t(k), rng);
    t.trace(
        u, kPoints, rng, [](const Eigen::Vector3d&, double) {}, c);
  }
  return log;
}

// rtcIntersect1 of the recorded rays whose kind is in the bit mask `kinds`, in order, nothing
// else; returns the number traced.
std::uint64_t replay(const MicroScene& sc, const std::vector<MicroRay>& rays, unsigned kinds) {
  auto* rs = static_cast<RTCScene>(sc.embree_scene());
  std::uint64_t n = 0;
  const auto size = static_cast<std::int64_t>(rays.size());
#pragma omp parallel for schedule(static, 4096) reduction(+ : n)
  for (std::int64_t i = 0; i < size; ++i) {
    const MicroRay& r = rays[i];
    if (!((kinds >> r.kind) & 1u)) continue;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    rh.ray.org_x = r.o[0];
    rh.ray.org_y = r.o[1];
    rh.ray.org_z = r.o[2];
    rh.ray.dir_x = r.d[0];
    rh.ray.dir_y = r.d[1];
    rh.ray.dir_z = r.d[2];
    rh.ray.tnear = 0;
    rh.ray.tfar = r.tfar;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.flags = 0;
    rh.ray.time = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(rs, &ctx, &rh);
    benchmark::DoNotOptimize(rh.hit.geomID);
    ++n;
  }
  return n;
}

struct Recording {
  std::vector<MicroRay> rays;
  TraceCounters counters;
};

// The rays of 8192 directions (seed 1), recorded once.
const Recording& recorded(const MicroScene& sc) {
  static Recording r;
  if (r.rays.empty()) r.rays = record_rays(sc, 8192, 1, r.counters);
  return r;
}

void BM_SimulateReplay(benchmark::State& state) {
  const MicroScene& sc = scene(false);
  const auto kinds = static_cast<unsigned>(state.range(0));
  const Recording& rec = recorded(sc);
  std::uint64_t n = 0;
  for (auto _ : state) n = replay(sc, rec.rays, kinds);
  state.counters["queries/s"] =
      benchmark::Counter(double(n), benchmark::Counter::kIsIterationInvariantRate);
  if (kinds == 15) {
    state.counters["rays_per_exit"] = double(n) / double(rec.counters.exits);
    state.counters["exits/s"] = benchmark::Counter(double(rec.counters.exits),
                                                   benchmark::Counter::kIsIterationInvariantRate);
  }
  state.SetLabel(kinds == 15  ? "all rays of the paths"
                 : kinds == 1 ? "first query of each incident ray"
                 : kinds == 6 ? "after a bounce, tile continuations"
                              : "escape rays decided without Embree");
}
// Kinds: 1 = incident rays' first queries, 6 = bounce rays and tile continuations, 8 = escape
// rays the tracer decides without a query, 15 = all (in their order: the yardstick).
BENCHMARK(BM_SimulateReplay)->Arg(15)->Arg(1)->Arg(6)->Arg(8)->Unit(benchmark::kMillisecond);

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

// The tracer alone (exits dropped) on the estimator's paths: `dirs` directions of `seed`.
TraceCounters trace_only(const MicroScene& sc, std::int64_t dirs, std::uint64_t seed) {
  std::vector<TraceCounters> cnt(omp_get_max_threads());
#pragma omp parallel
  {
    MicroTracer t(sc, TraceOptions{});
    auto& c = cnt[omp_get_thread_num()];
#pragma omp for schedule(static, 16)
    for (std::int64_t k = 0; k < dirs; ++k) {
      SimRng rng(0);
      const Eigen::Vector3d u = direction(seed, std::uint64_t(k), rng);
      t.trace(
          u, kPoints, rng, [](const Eigen::Vector3d&, double) {}, c);
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
  for (auto _ : state) total.merge(trace_only(sc, 4096, ++round));
  state.counters["queries/s"] = benchmark::Counter(double(total.segments) / double(round),
                                                   benchmark::Counter::kIsIterationInvariantRate);
  state.counters["exits/s"] = benchmark::Counter(double(total.exits) / double(round),
                                                 benchmark::Counter::kIsIterationInvariantRate);
  state.counters["queries_per_ray"] = double(total.segments) / double(total.incident_rays);
  state.counters["exits_without_query"] = double(total.escapes_bounded) / double(total.exits);
  state.SetLabel(state.range(0) ? "grid" : "triangles");
}
BENCHMARK(BM_SimulateTracer)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_SimulateEstimator(benchmark::State& state) {
  const MicroScene& sc = scene(false);
  SimulateOptions o;
  o.lmax = static_cast<int>(state.range(0));
  o.incident_directions = 8192;
  o.points = kPoints;
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
BENCHMARK(BM_SimulateEstimator)->Arg(15)->Arg(8)->Arg(1)->Unit(benchmark::kMillisecond);

// One run, interleaved, 1 and 2 threads, each timed `reps` times on the same 8192 directions of
// seed 1 (lmax 15, 16 points): the replay of all rays of those paths (the yardstick), the tracer
// alone and the estimator, plus the older random-ray loop. Rates per second of process CPU (all
// threads: what the work costs, independent of how much of the machine the process got).
//   ratio_cpu = estimator exits per CPU s / exits per CPU s of the bare replay of the same paths
//             = (bare Embree CPU for the rays of the paths) / (estimator CPU for the paths)
// pooled over the repetitions; ratio_cpu_min / _max: the spread of the ratio of each
// repetition's back-to-back pair (the machine's load moves the rates by 10-20 % within a run).
// ratio_cpu_queried: the same against a replay of only the queries the tracer still sends.
//
// CPU of one thread over two for the same work, X_cpu_1t_over_2t (pooled; _med, _min, _max over
// the repetitions), for the estimator (est), the bare replay (bare) and two machine yardsticks
// (bench_cpu.hpp) timed in the same repetitions: a register-only loop (compute) and a dependent
// random walk over 128 MiB, four times the L3 (chase). est_excess_over_chase / _over_bare: the
// estimator's ratio over the machine's, pooled, with the spread of the per-repetition quotients:
// what one thread costs the estimator beyond what it costs a loop of DRAM reads or bare Embree.
// Each repetition runs both thread counts back to back, 1 then 2 in even repetitions, 2 then 1
// in odd ones.
void BM_SimulateSummary(benchmark::State& state) {
  const double load0 = microbrdf::bench::load_average();
  const MicroScene& sc = scene(false);
  const Recording& rec = recorded(sc);
  const double busy0 = microbrdf::bench::machine_busy_cpu(), own0 = process_cpu(), wall0 = wall();
  static const microbrdf::bench::PointerChase chase(std::size_t{128} << 20);
  const std::int64_t batch = 1 << 17;
  const std::uint64_t compute_steps = std::uint64_t{1} << 26, chase_steps = std::uint64_t{1} << 21;
  const int reps = static_cast<int>(state.range(0));
  struct Rate {
    double cpu = 0, best_wall = 1e30, work = 0, rays = 0;
    std::vector<double> per_rep;  // work per CPU second of each repetition
    void add(double c, double w, double done, double r = 0) {
      cpu += c;
      best_wall = std::min(best_wall, w);
      work += done;
      rays += r;
      per_rep.push_back(done / c);
    }
  };
  Rate replayed[2], queried[2], random[2], est[2], tracer[2], compute[2], chased[2];
  std::uint64_t round = 0;
  for (auto _ : state) {
    for (int rep = 0; rep < reps; ++rep)
      for (int nt : rep % 2 == 0 ? std::array{1, 2} : std::array{2, 1}) {
        double c0 = process_cpu(), w0 = wall();
        benchmark::DoNotOptimize(microbrdf::bench::compute_loop(nt, compute_steps));
        compute[nt - 1].add(process_cpu() - c0, wall() - w0, double(compute_steps));
        c0 = process_cpu();
        w0 = wall();
        benchmark::DoNotOptimize(chase.run(nt, chase_steps));
        chased[nt - 1].add(process_cpu() - c0, wall() - w0, double(chase_steps));
        const int before = omp_get_max_threads();
        omp_set_num_threads(nt);
        c0 = process_cpu();
        w0 = wall();
        const double n = double(replay(sc, rec.rays, 15));
        replayed[nt - 1].add(process_cpu() - c0, wall() - w0, double(rec.counters.exits), n);
        c0 = process_cpu();
        w0 = wall();
        const double q = double(replay(sc, rec.rays, 7));
        queried[nt - 1].add(process_cpu() - c0, wall() - w0, double(rec.counters.exits), q);
        c0 = process_cpu();
        w0 = wall();
        const TraceCounters tc = trace_only(sc, 8192, 1);
        tracer[nt - 1].add(process_cpu() - c0, wall() - w0, double(tc.exits));
        c0 = process_cpu();
        w0 = wall();
        benchmark::DoNotOptimize(bare_rays(sc, batch, ++round));
        random[nt - 1].add(process_cpu() - c0, wall() - w0, double(batch), double(batch));
        omp_set_num_threads(before);
        SimulateOptions o;
        o.lmax = 15;
        o.points = kPoints;
        o.incident_directions = 8192;
        o.threads = nt;
        o.seed = 1;
        SimulateStats st;
        c0 = process_cpu();
        w0 = wall();
        benchmark::DoNotOptimize(simulate(sc, o, &st));
        est[nt - 1].add(process_cpu() - c0, wall() - w0, double(st.counters.exits));
      }
  }
  for (int i = 0; i < 2; ++i) {
    const std::string t = i == 0 ? "_1t" : "_2t";
    const double bare_exits = replayed[i].work / replayed[i].cpu;
    const double bare_rays = replayed[i].rays / replayed[i].cpu;
    const double exits = est[i].work / est[i].cpu;
    state.counters["bare_rays_per_cpu_s" + t] = bare_rays;
    state.counters["bare_exits_per_cpu_s" + t] = bare_exits;
    state.counters["exits_per_cpu_s" + t] = exits;
    state.counters["ratio_cpu" + t] = exits / bare_exits;
    double lo = 1e30, hi = 0;
    for (std::size_t r = 0; r < est[i].per_rep.size(); ++r) {
      const double q = est[i].per_rep[r] / replayed[i].per_rep[r];
      lo = std::min(lo, q);
      hi = std::max(hi, q);
    }
    state.counters["ratio_cpu_min" + t] = lo;
    state.counters["ratio_cpu_max" + t] = hi;
    state.counters["ratio_wall" + t] = replayed[i].best_wall / est[i].best_wall;
    // The tracer alone (no spherical harmonics): the ceiling of ratio_cpu.
    state.counters["tracer_ratio_cpu" + t] = (tracer[i].work / tracer[i].cpu) / bare_exits;
    // Against the replay of only the queries the tracer still makes (the escape rays it decides
    // without Embree left out): the estimator's time over its own Embree time, all overheads.
    state.counters["ratio_cpu_queried" + t] = exits / (queried[i].work / queried[i].cpu);
    // Exits per bare ray of the replay, and per random ray of the older loop.
    state.counters["exits_per_bare_ray" + t] = exits / bare_rays;
    state.counters["exits_per_random_ray" + t] = exits / (random[i].rays / random[i].cpu);
  }
  state.counters["rays_per_exit"] = double(rec.rays.size()) / double(rec.counters.exits);
  state.counters["queries_per_exit"] = double(rec.counters.segments) / double(rec.counters.exits);
  state.counters["exits_without_query"] =
      double(rec.counters.escapes_bounded) / double(rec.counters.exits);
  // CPU per unit of work with one thread over two: pooled, and the per-repetition ratios.
  auto per_rep = [](const Rate* r) {
    std::vector<double> q(r[0].per_rep.size());
    for (std::size_t k = 0; k < q.size(); ++k) q[k] = r[1].per_rep[k] / r[0].per_rep[k];
    return q;
  };
  auto put_spread = [&](const std::string& name, double pooled, std::vector<double> q) {
    state.counters[name] = pooled;
    std::sort(q.begin(), q.end());
    const std::size_t m = q.size();
    state.counters[name + "_med"] = m % 2 ? q[m / 2] : 0.5 * (q[m / 2 - 1] + q[m / 2]);
    state.counters[name + "_min"] = q.front();
    state.counters[name + "_max"] = q.back();
  };
  auto pooled = [](const Rate* r) { return (r[1].work / r[1].cpu) / (r[0].work / r[0].cpu); };
  const std::vector<double> q_est = per_rep(est), q_bare = per_rep(replayed),
                            q_chase = per_rep(chased);
  // The goal: est_cpu_1t_over_2t never above 1, or no higher than the machine's own ratios.
  put_spread("est_cpu_1t_over_2t", pooled(est), q_est);
  put_spread("bare_cpu_1t_over_2t", pooled(replayed), q_bare);
  put_spread("chase_cpu_1t_over_2t", pooled(chased), q_chase);
  put_spread("compute_cpu_1t_over_2t", pooled(compute), per_rep(compute));
  std::vector<double> over_chase(q_est.size()), over_bare(q_est.size());
  for (std::size_t k = 0; k < q_est.size(); ++k) {
    over_chase[k] = q_est[k] / q_chase[k];
    over_bare[k] = q_est[k] / q_bare[k];
  }
  put_spread("est_excess_over_chase", pooled(est) / pooled(chased), over_chase);
  put_spread("est_excess_over_bare", pooled(est) / pooled(replayed), over_bare);
  // Nanoseconds of CPU per step of the two machine loops (one thread, two threads).
  state.counters["chase_ns_per_step_1t"] = 1e9 * chased[0].cpu / chased[0].work;
  state.counters["chase_ns_per_step_2t"] = 1e9 * chased[1].cpu / chased[1].work;
  state.counters["compute_ns_per_step_1t"] = 1e9 * compute[0].cpu / compute[0].work;
  // Cores' worth of CPU that other processes took during the repetitions (0 = none, 2 = both).
  state.counters["others_cores"] =
      (microbrdf::bench::machine_busy_cpu() - busy0 - (process_cpu() - own0)) / (wall() - wall0);
  state.counters["reps"] = reps;
  state.counters["load_before"] = load0;
  state.counters["load_after"] = microbrdf::bench::load_average();
  state.SetLabel("lmax 15, 16 points, 524288 triangles; rates per process CPU second");
}
BENCHMARK(BM_SimulateSummary)->Arg(40)->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace
