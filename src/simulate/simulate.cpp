// The W92 estimator driver: incident directions in fixed blocks over OpenMP threads, one
// ShEstimator per thread, merged in thread order (deterministic for a seed and thread count).
#include "microbrdf/simulate.hpp"

#include <omp.h>

#include <chrono>
#include <cmath>

#include "microbrdf/error.hpp"
#include "microbrdf/threads.hpp"

namespace microbrdf {

double SimulateStats::exit_rays_per_second() const {
  return seconds > 0 ? static_cast<double>(counters.exits) / seconds : 0.0;
}

nlohmann::json SimulateStats::to_json() const {
  const double n = std::max<double>(1.0, static_cast<double>(counters.incident_rays));
  return {{"incident_directions", incident_directions},
          {"incident_rays", counters.incident_rays},
          {"exit_rays", counters.exits},
          {"embree_queries", counters.segments},
          {"seconds", seconds},
          {"threads", threads},
          {"exit_rays_per_second", exit_rays_per_second()},
          {"embree_queries_per_second", seconds > 0 ? counters.segments / seconds : 0.0},
          {"q", q},
          {"mean_exit_energy", counters.energy_out / n},
          {"energy_below", counters.energy_down / n},
          {"energy_depth_capped", counters.energy_capped / n},
          {"paths_depth_capped", counters.capped},
          {"energy_lost", counters.energy_lost / n}};
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
  // Directions go in rounds of a fixed size (independent of the thread count); inside a round
  // the first g^2 are stratified on a g x g grid of (cos theta, phi) -- still uniform over the
  // hemisphere, with far less variance from the incident side than independent draws.
  const std::uint64_t round = 1024, g = 32, block = 16;
  std::vector<ShEstimator> est(nt, ShEstimator(o.lmax));
  std::vector<TraceCounters> cnt(nt);
  const int J = est[0].basis().size();
  const double pdf_u = 1 / (2 * M_PI);
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  double last_report = 0;
  std::uint64_t done = 0;
  for (;;) {
    std::uint64_t n = round;
    if (o.time_limit_s <= 0) n = std::min(n, o.incident_directions - done);
    if (n == 0) break;
#pragma omp parallel num_threads(nt)
    {
      const int tid = omp_get_thread_num();
      MicroTracer tracer(scene, o.trace);
      const ShOddBasis& basis = est[tid].basis();
      std::vector<double> y(J), sum(J);
#pragma omp for schedule(static, block)
      for (std::int64_t k = 0; k < static_cast<std::int64_t>(n); ++k) {
        const std::uint64_t idx = done + static_cast<std::uint64_t>(k);
        SimRng rng(o.seed, idx);
        double u1 = rng.uniform(), u2 = rng.uniform();
        if (o.stratify && static_cast<std::uint64_t>(k) < g * g && n == round) {
          u1 = (double(std::uint64_t(k) % g) + u1) / double(g);
          u2 = (double(std::uint64_t(k) / g) + u2) / double(g);
        }
        const Eigen::Vector3d u = uniform_hemisphere(u1, u2);
        std::fill(sum.begin(), sum.end(), 0.0);
        double energy = 0;
        // Amortised update (W92 eq. 25): R Y(V) summed over all exits of this direction, one
        // outer product per direction inside the estimator.
        tracer.trace(
            u, o.points, rng,
            [&](const Eigen::Vector3d& v, double r) {
              basis.eval(v, y.data());
              for (int j = 0; j < J; ++j) sum[j] += r * y[j];
              energy += r;
            },
            cnt[tid]);
        est[tid].add_incident(u, pdf_u, sum.data(), static_cast<std::size_t>(o.points), energy);
      }
    }
    done += n;
    const double t = elapsed();
    const bool finished = o.time_limit_s > 0 ? t >= o.time_limit_s : done >= o.incident_directions;
    if (o.progress && (t - last_report >= 1.0 || finished)) {
      last_report = t;
      ShEstimator merged = est[0];
      std::uint64_t rays = cnt[0].incident_rays;
      for (int i = 1; i < nt; ++i) {
        merged.merge(est[i]);
        rays += cnt[i].incident_rays;
      }
      o.progress(done, rays, t, merged.q());
    }
    if (finished) break;
  }
  ShEstimator out = est[0];
  TraceCounters total = cnt[0];
  for (int i = 1; i < nt; ++i) {
    out.merge(est[i]);
    total.merge(cnt[i]);
  }
  if (stats) {
    stats->counters = total;
    stats->incident_directions = done;
    stats->seconds = elapsed();
    stats->threads = nt;
    stats->q = out.q();
  }
  return out;
}

}  // namespace microbrdf
