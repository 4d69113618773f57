#pragma once
// The Westin-Arvo-Torrance 1992 Monte Carlo BRDF simulation on a MicroScene (docs/westin.md,
// "Estimator"): rays from uniformly drawn incident directions U hit the tile at uniform points
// (N_p per direction), scatter through the microgeometry (N_b branches at the first diffuse
// event), and every exit (direction V, energy fraction R) feeds the estimator of docs/theory.md
// §6.4,
//   m~_jk = (1/N) sum 8 pi cos(theta_U) Y_j(U) R Y_k(V)      (uniform U, odd completion),
// which is W92 eq. 25 for f = rho cos(theta_i) cos(theta_r): the radiance conversion (divide by
// cos theta_r, W92 section 4) and the cosine of the representation cancel, so R enters as is.
//
// Energy bookkeeping: a ray carries the fraction of the incident flux it stands for. Mirrors
// multiply it by F; a dielectric reflects with probability F and refracts otherwise (analog, no
// weight change), and e^{-absorption s} along paths inside; diffuse materials multiply it by
// their sampling weight (f cos / pdf) and split it over N_b branches the first time. After
// `rr_depth` events Russian roulette ends weak paths (unbiased); `max_depth` caps the rest and
// the capped energy is reported. The R of all exits of one incident ray sum, on average, to the
// directional albedo.

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "microbrdf/distribute.hpp"
#include "microbrdf/microscene.hpp"
#include "microbrdf/sh_basis.hpp"

namespace microbrdf {

/// A small fast generator (SplitMix64); one stream per incident direction so the result does
/// not depend on how directions are shared between threads.
class SimRng {
 public:
  explicit SimRng(std::uint64_t seed, std::uint64_t stream = 0);
  std::uint64_t next();
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  ///< [0, 1)

 private:
  std::uint64_t s_;
};

/// Bounds on the counts a user sets (each path keeps its branches on a stack; a direction's
/// points are traced before the next direction starts).
inline constexpr int kMaxBranches = 4096;
inline constexpr int kMaxPointsPerDirection = 1 << 20;

struct TraceOptions {
  int branches = 1;     ///< N_b: rays spawned at the first diffuse event of a path (1..4096)
  int max_depth = 100;  ///< scattering events before a path is cut (reported)
  int rr_depth = 6;     ///< Russian roulette from this many events on
};

/// Per-thread counters of what happened to the energy.
struct TraceCounters {
  std::uint64_t incident_rays = 0;    ///< rays started (N_i N_p)
  std::uint64_t exits = 0;            ///< exit rays (escaped upwards)
  std::uint64_t segments = 0;         ///< Embree queries
  std::uint64_t escapes_bounded = 0;  ///< exits decided by MicroScene::clears_upward (no query)
  std::uint64_t capped = 0;           ///< paths cut at max_depth
  double energy_out = 0;              ///< sum of exit R
  double energy_down = 0;             ///< sum of R that left through the bottom
  double energy_capped = 0;           ///< sum of R cut at max_depth
  double energy_lost = 0;             ///< rays running parallel to the plane
  void merge(const TraceCounters& o);
};

/// Traces rays for one incident direction. Not thread-safe (scratch stack): one per thread.
class MicroTracer {
 public:
  MicroTracer(const MicroScene& scene, const TraceOptions& options);
  /// `u`: unit direction towards the light in the BRDF frame (u.z > 0); `points` rays start
  /// towards uniform points of the tile; `exit(v, r)` is called for every exit ray (v in the
  /// BRDF frame, r its energy fraction of one incident ray).
  template <class Exit>
  void trace(const Eigen::Vector3d& u, int points, SimRng& rng, Exit&& exit, TraceCounters& c);
  /// Benchmarks: append every ray of the paths to `log` as MicroScene::trace issues it (escape
  /// rays decided without Embree as the queries they replace, kind 3); nullptr stops logging.
  void log_rays(std::vector<MicroRay>* log) { log_ = log; }

 private:
  struct Path {
    Eigen::Vector3d o, d;
    double w, w0;
    double kappa;  // Beer coefficient of the medium the ray travels in, 1/m
    int depth;
    bool branched;
  };
  // Follows one path; pushes branches on stack_. Returns true (and v, w) for an exit.
  bool follow(Path& path, SimRng& rng, TraceCounters& c, Eigen::Vector3d& v);
  const MicroScene& scene_;
  TraceOptions opt_;
  std::vector<Path> stack_;
  std::vector<MicroRay>* log_ = nullptr;
};

template <class Exit>
void MicroTracer::trace(const Eigen::Vector3d& u, int points, SimRng& rng, Exit&& exit,
                        TraceCounters& c) {
  const Eigen::Vector3d d = -scene_.to_scene(u);
  const double top = scene_.zmax();
  for (int p = 0; p < points; ++p) {
    ++c.incident_rays;
    stack_.push_back(
        Path{Eigen::Vector3d(rng.uniform() * scene_.width(), rng.uniform() * scene_.height(), top),
             d, 1.0, 1.0, 0.0, 0, false});
    while (!stack_.empty()) {
      Path path = stack_.back();
      stack_.pop_back();
      Eigen::Vector3d v;
      if (follow(path, rng, c, v)) {
        ++c.exits;
        c.energy_out += path.w;
        exit(scene_.to_brdf(v), path.w);
      }
    }
  }
}

/// Uniform direction on the upper hemisphere (density 1 / (2 pi)).
Eigen::Vector3d uniform_hemisphere(double u1, double u2);

struct SimulateOptions {
  int lmax = 15;
  std::uint64_t incident_directions = 20000;  ///< N_i in all (ignored when time_limit_s > 0)
  double time_limit_s = 0;                    ///< > 0: run until this wall time instead
  int points = 16;                            ///< N_p per incident direction
  TraceOptions trace;
  std::uint64_t seed = 1;
  int threads = 0;  ///< 0 = OpenMP default
  /// Stratify the incident directions in rounds of 1024 (32 x 32 cells in cos(theta) and phi);
  /// false = independent uniform draws as in W92.
  bool stratify = true;
  /// Called about once a second from one thread: directions done, rays, seconds, Q.
  std::function<void(std::uint64_t, std::uint64_t, double, double)> progress;
};

struct SimulateStats {
  TraceCounters counters;
  std::uint64_t incident_directions = 0;
  double seconds = 0;
  double q = 0;
  int threads = 1;
  WorkStats work;  ///< blocks and seconds per MPI rank
  double exit_rays_per_second() const;
  nlohmann::json to_json() const;
};

/// Runs the estimator over all threads and MPI ranks (distribute.hpp): blocks of 256 incident
/// directions, each traced single-threaded into its own estimator and merged on rank 0 in block
/// order. Direction k always draws from random stream (seed, k), so with incident_directions
/// the matrix is bit-identical for any number of threads and ranks (not with time_limit_s,
/// where the number of directions depends on the speed). On ranks other than 0 the returned
/// estimator is empty and `stats` untouched.
ShEstimator simulate(const MicroScene& scene, const SimulateOptions& options,
                     SimulateStats* stats = nullptr);

/// Direct "goniometer" estimate for one incident direction, without spherical harmonics: the
/// cosine-weighted mean of rho over a cone of half-angle `half_angle` (rad) around each of
/// `dirs` (BRDF frame, cones above the horizon): rho_cap = sum of R in the cone /
/// (N pi sin^2(half_angle) cos(theta_c)). Threads with fixed blocks; deterministic.
/// `average_azimuth`: for statistically isotropic scenes, each block of rays turns the plane of
/// incidence (and the cones with it) to a stratified random azimuth, so one finite realisation
/// of the surface is sampled in all orientations (its own anisotropy averages out).
std::vector<double> cap_brdf(const MicroScene& scene, const Eigen::Vector3d& u,
                             const std::vector<Eigen::Vector3d>& dirs, double half_angle,
                             std::uint64_t rays, const TraceOptions& trace, std::uint64_t seed,
                             TraceCounters* counters = nullptr, bool average_azimuth = false,
                             int points_per_block = 64);

/// A fraction estimated from `samples` Bernoulli-weighted samples, with its standard error.
struct FractionEstimate {
  double value = 0, std_error = 0;
  std::uint64_t samples = 0;
};
/// Ray-traced Smith visibility of a height-field scene seen from polar angle theta (rad; azimuth
/// drawn uniformly per sample): the projected area of the surface facing the viewer that is not
/// occluded, over all of it facing the viewer -- the G1(v) of microfacet theory (Smith's
/// 1 / (1 + Lambda) for Gaussian surfaces), and Dong 2015 Fig. 6 left ("average fraction of the
/// surface visible"). Surface points come from vertical rays at uniform points of the tile.
FractionEstimate visible_fraction(const MicroScene& scene, double theta, std::uint64_t samples,
                                  std::uint64_t seed);
/// Sun 2002's free travel probability on a 2-D surface: rays leaving surface points within
/// +-band of the mean plane z = 0 (band in metres), in directions at polar angle theta with
/// uniform azimuth that the local facet faces, and the fraction that escape without hitting the
/// surface (compare sun2002::ftp and sun2002::smith_at_mean_plane).
FractionEstimate free_travel_probability(const MicroScene& scene, double theta, double band,
                                         std::uint64_t samples, std::uint64_t seed);

/// He, Torrance, Sillion & Greenberg 1991 directional-diffuse term in its geometric-optics limit
/// (docs/theory.md §6.7): F(wi.h) S(theta_i) S(theta_r) D_Beckmann(h; alpha = 2 sigma_0 / tau) /
/// (4 cos theta_i cos theta_r), with He's shadowing S (errata form with exp(-a^2); `errata` =
/// false gives the printed eq. 25) and the effective roughness sigma_0(theta_i, theta_r).
/// sigma, tau in metres (C(r) = sigma^2 exp(-r^2 / tau^2)); fresnel null = 1. 1/sr.
double he1991_geometric_brdf(const Eigen::Vector3d& wi, const Eigen::Vector3d& wo, double sigma,
                             double tau, bool errata = true, const Fresnel* fresnel = nullptr,
                             double wavelength_m = 550e-9);

}  // namespace microbrdf
