// The W92 estimator driver: incident directions in fixed blocks, each block traced into its own
// ShEstimator by whichever thread or MPI rank takes it (distribute.hpp), and the blocks merged on
// rank 0 in block order. Direction k always draws from random stream (seed, k) and a block's
// directions are added in index order, so the matrix is bit-identical for any number of threads
// and ranks (docs/scale.md).
#include "microbrdf/simulate.hpp"

#include <omp.h>

#include <chrono>
#include <cmath>
#include <limits>

#include "microbrdf/distribute.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/threads.hpp"

namespace microbrdf {
namespace {

// Directions come in rounds of 1024 whose directions are stratified on a 32 x 32 grid of
// (cos theta, phi) when the round is complete (still uniform over the hemisphere, with far less
// variance from the incident side than independent draws); a round is traced as 4 blocks.
constexpr std::uint64_t kRound = 1024, kGrid = 32, kBlock = 256, kBlocksPerRound = kRound / kBlock;

constexpr std::size_t kCounters = 9;

void pack_counters(const TraceCounters& c, std::vector<double>& v) {
  // Counts below 2^53 travel exactly as doubles.
  v.insert(v.end(),
           {static_cast<double>(c.incident_rays), static_cast<double>(c.exits),
            static_cast<double>(c.segments), static_cast<double>(c.capped), c.energy_out,
            c.energy_down, c.energy_capped, c.energy_lost, static_cast<double>(c.escapes_bounded)});
}

TraceCounters unpack_counters(const double* v) {
  TraceCounters c;
  c.incident_rays = static_cast<std::uint64_t>(v[0]);
  c.exits = static_cast<std::uint64_t>(v[1]);
  c.segments = static_cast<std::uint64_t>(v[2]);
  c.capped = static_cast<std::uint64_t>(v[3]);
  c.energy_out = v[4];
  c.energy_down = v[5];
  c.energy_capped = v[6];
  c.energy_lost = v[7];
  c.escapes_bounded = static_cast<std::uint64_t>(v[8]);
  return c;
}

// Traces directions [first, first + count) of a run of `total` directions (0 = open-ended, every
// round complete) into a fresh estimator; returns its state and the counters.
WorkResult trace_block(const MicroScene& scene, const SimulateOptions& o, std::uint64_t first,
                       std::uint64_t count, std::uint64_t total) {
  // One thread per block, whatever the caller's OpenMP setting: with --threads 1 the work pool
  // hands its single worker every core for "inner" parallelism, and a matrix product inside
  // would then open an OpenMP team whose second thread mostly waits (7-14% more CPU than
  // --threads 2 for the same work, measured).
  struct OneOmpThread {
    int before = omp_get_max_threads();
    OneOmpThread() { omp_set_num_threads(1); }
    ~OneOmpThread() { omp_set_num_threads(before); }
  } one_thread;
  ShEstimator est(o.lmax);
  TraceCounters cnt;
  MicroTracer tracer(scene, o.trace);
  const ShOddBasis& basis = est.basis();
  const int J = basis.size();
  const double pdf_u = 1 / (2 * M_PI);
  std::vector<double> sum(J), weights;
  std::vector<Vec3> exits;
  for (std::uint64_t idx = first; idx < first + count; ++idx) {
    SimRng rng(o.seed, idx);
    double u1 = rng.uniform(), u2 = rng.uniform();
    const std::uint64_t k = idx % kRound;
    const bool full_round = total == 0 || (idx / kRound + 1) * kRound <= total;
    if (o.stratify && full_round) {
      u1 = (double(k % kGrid) + u1) / double(kGrid);
      u2 = (double(k / kGrid) + u2) / double(kGrid);
    }
    const Eigen::Vector3d u = uniform_hemisphere(u1, u2);
    double energy = 0;
    // Amortised update (W92 eq. 25): R Y(V) summed over all exits of this direction (the exits
    // gathered and projected four at a time), one outer product per direction inside the
    // estimator.
    exits.clear();
    weights.clear();
    tracer.trace(
        u, o.points, rng,
        [&](const Eigen::Vector3d& v, double r) {
          exits.push_back(v);
          weights.push_back(r);
          energy += r;
        },
        cnt);
    basis.eval_sum(exits.size(), exits.data(), weights.data(), sum.data());
    est.add_incident(u, pdf_u, sum.data(), static_cast<std::size_t>(o.points), energy);
  }
  WorkResult r;
  r.values = est.pack();
  pack_counters(cnt, r.values);
  return r;
}

}  // namespace

double SimulateStats::exit_rays_per_second() const {
  return seconds > 0 ? static_cast<double>(counters.exits) / seconds : 0.0;
}

nlohmann::json SimulateStats::to_json() const {
  const double n = std::max<double>(1.0, static_cast<double>(counters.incident_rays));
  return {{"incident_directions", incident_directions},
          {"incident_rays", counters.incident_rays},
          {"exit_rays", counters.exits},
          {"embree_queries", counters.segments},
          {"exits_without_query", counters.escapes_bounded},
          {"seconds", seconds},
          {"threads", threads},
          {"exit_rays_per_second", exit_rays_per_second()},
          {"embree_queries_per_second", seconds > 0 ? counters.segments / seconds : 0.0},
          {"q", q},
          {"mean_exit_energy", counters.energy_out / n},
          {"energy_below", counters.energy_down / n},
          {"energy_depth_capped", counters.energy_capped / n},
          {"paths_depth_capped", counters.capped},
          {"energy_lost", counters.energy_lost / n},
          {"mpi", work.to_json("blocks_per_rank")}};
}

ShEstimator simulate(const MicroScene& scene, const SimulateOptions& o, SimulateStats* stats) {
  if (o.lmax < 1 || o.lmax > 64) throw InputError("simulate: lmax must be in [1, 64]");
  if (o.trace.branches > kMaxBranches)  // checked here: the tracers are built in the workers
    throw InputError("simulate: branches must lie in 1.." + std::to_string(kMaxBranches) +
                     " (--branches)");
  if (o.points < 1 || o.points > kMaxPointsPerDirection)
    throw InputError("simulate: points per direction must lie in 1.." +
                     std::to_string(kMaxPointsPerDirection) + " (--points)");
  if (o.time_limit_s <= 0 && o.incident_directions == 0)
    throw InputError("simulate: give a number of incident directions or a time limit");
  const int nt = resolve_thread_count(o.threads);
  const bool timed = o.time_limit_s > 0;
  const std::uint64_t total = timed ? 0 : o.incident_directions;
  // Timed runs hand out blocks until the time is up, always finishing the round they are in.
  const std::uint64_t blocks =
      timed ? std::numeric_limits<std::uint64_t>::max() / kRound : (total + kBlock - 1) / kBlock;
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  ShEstimator out(o.lmax);
  TraceCounters counters;
  std::uint64_t done = 0;
  double last_report = 0;
  const std::size_t state = static_cast<std::size_t>(out.basis().size()) * out.basis().size() + 3;
  DistributeOptions d;
  d.threads = nt;  // one block per thread, traced single-threaded (no nested parallelism)
  if (timed)
    d.keep_going = [&](std::size_t b) {
      return b % kBlocksPerRound != 0 || elapsed() < o.time_limit_s;
    };
  std::vector<double> packed;
  const WorkStats work = distribute(
      blocks,
      [&](std::size_t b) {
        const std::uint64_t first = b * kBlock;
        const std::uint64_t count = timed ? kBlock : std::min(kBlock, total - first);
        return trace_block(scene, o, first, count, total);
      },
      [&](std::size_t, WorkResult&& r) {
        if (r.values.size() != state + kCounters)
          throw std::runtime_error("simulate: a block's result has the wrong size");
        const TraceCounters c = unpack_counters(r.values.data() + state);
        r.values.resize(state);
        out.merge_packed(r.values);
        counters.merge(c);
        done = out.incident_count();
        const double t = elapsed();
        if (o.progress && t - last_report >= 1.0) {
          last_report = t;
          o.progress(done, counters.incident_rays, t, out.q());
        }
      },
      d);
  if (stats && mpi_is_root()) {
    stats->counters = counters;
    stats->incident_directions = done;
    stats->seconds = elapsed();
    stats->threads = nt;
    stats->q = out.q();
    stats->work = work;
  }
  if (o.progress && mpi_is_root()) o.progress(done, counters.incident_rays, elapsed(), out.q());
  return out;
}

}  // namespace microbrdf
