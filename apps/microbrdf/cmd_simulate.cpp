// `microbrdf simulate SCENE.json`: Westin 1992 SH-matrix BRDF by Monte Carlo ray tracing of a
// micro-scene (Embree), and a direct in-plane "goniometer" mode compared with He 1991 /
// Beckmann-Smith.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>

#include "cli_common.hpp"
#include "cli_threads.hpp"
#include "commands.hpp"
#include "microbrdf/atomic_file.hpp"
#include "microbrdf/duration.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/goniometer.hpp"
#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/plot.hpp"
#include "microbrdf/sh_basis.hpp"
#include "microbrdf/sh_brdf.hpp"
#include "microbrdf/simulate.hpp"
#include "microbrdf/units.hpp"
#include "simulate_args.hpp"

namespace microbrdf::cli {
namespace {

using namespace simulate_cli;

double parse_seconds(const std::string& t) { return parse_duration(t, "--time"); }

void run_sh(const SimArgs& a, const MicroScene& scene) {
  if (a.output.empty()) throw InputError("-o OUT.shbrdf is required (or use --in-plane)");
  SimulateOptions o;
  o.lmax = a.lmax;
  o.points = a.points;
  o.trace = trace_options(a);
  o.seed = a.seed;
  o.threads = bounded_threads("simulate", a.threads);
  o.stratify = !a.independent;
  if (!a.time.empty()) {
    o.time_limit_s = parse_seconds(a.time);
    if (!(o.time_limit_s > 0)) throw InputError("--time must be positive");
  } else {
    if (a.rays < 1) throw InputError("--rays must be >= 1");
    if (a.points < 1 || std::uint64_t(a.points) > a.rays)
      throw InputError("--points must lie in 1..--rays (" + std::to_string(a.rays) + ")");
    o.incident_directions = std::max<std::uint64_t>(1, a.rays / std::uint64_t(a.points));
  }
  Progress progress("simulate", a.quiet);
  if (!a.quiet)
    o.progress = [&progress](std::uint64_t dirs, std::uint64_t rays, double t, double q) {
      char b[160];
      std::snprintf(b, sizeof b, "%llu directions, %.3g rays, %.1f s, %.3g rays/s, Q = %.3g",
                    static_cast<unsigned long long>(dirs), double(rays), t,
                    t > 0 ? double(rays) / t : 0.0, q);
      progress.status(b);
    };
  SimulateStats st;
  const ShEstimator est = simulate(scene, o, &st);
  if (!mpi_is_root()) return;  // rank 0 writes the matrix
  nlohmann::json meta = {{"generator", "microbrdf simulate (Westin 1992)"},
                         {"scene", a.scene},
                         {"scene_name", scene.desc().name},
                         {"scene_json", scene.desc().source},
                         {"wavelength_m", scene.desc().wavelength_m},
                         {"seed", a.seed},
                         {"points_per_direction", a.points},
                         {"branches", a.branches},
                         {"max_depth", a.max_depth},
                         {"stratified", o.stratify},
                         {"stats", st.to_json()}};
  const ShBrdf brdf = ShBrdf::from_estimator(est, meta);
  brdf.save(a.output);
  if (a.json) {
    nlohmann::json j = st.to_json();
    j["output"] = a.output;
    j["lmax"] = a.lmax;
    j["size"] = brdf.basis().size();
    j["scene"] = a.scene;
    j["triangles"] = scene.triangle_count();
    j["primitives"] = scene.capsule_count();
    j["albedo_normal"] = brdf.albedo(Eigen::Vector3d(0, 0, 1));
    print_json(j);
  } else if (!a.quiet) {
    std::fprintf(stderr, "microbrdf simulate: wrote %s (lmax %d, %d x %d), Q = %.3g\n",
                 a.output.c_str(), a.lmax, brdf.basis().size(), brdf.basis().size(), st.q);
  }
}

void run(const SimArgs& a) {
  if (a.visibility || !a.in_plane.empty()) {
    // The direct modes run on rank 0 alone (docs/scale.md).
    if (!mpi_is_root()) return;
    mpi_set_solo(true);
  }
  // The scene's own inconsistencies (a height field that does not fit the tile, no geometry)
  // are the scene file's: named as such.
  std::optional<MicroScene> built;
  about_file(a.scene, [&] { built.emplace(load_micro_scene(a.scene)); });
  MicroScene& scene = *built;
  if (!a.quiet)
    std::fprintf(stderr,
                 "microbrdf simulate: scene '%s': tile %s x %s, %zu triangles, %zu analytic "
                 "primitives\n",
                 scene.desc().name.c_str(), format_length(scene.width()).c_str(),
                 format_length(scene.height()).c_str(), scene.triangle_count(),
                 scene.capsule_count());
  if (a.visibility)
    run_visibility(a, scene);
  else if (!a.in_plane.empty())
    run_in_plane(a, scene);
  else
    run_sh(a, scene);
}

}  // namespace

void register_simulate(CLI::App& app) {
  auto a = std::make_shared<SimArgs>();
  auto* c = app.add_subcommand(
      "simulate", "Westin 1992: SH-matrix BRDF of a micro-scene by Monte Carlo ray tracing");
  c->footer(
      "Rays from uniformly drawn incident directions (N_i = rays / points) hit the scene's tile "
      "at\n"
      "uniform points (--points per direction); the tile repeats periodically, so there are no\n"
      "edge effects. Exits feed the estimator of docs/theory.md §6.4 (W92 eqs. 17, 25); the matrix "
      "is\n"
      "symmetrised and written as .shbrdf (see `microbrdf brdf slice --sh`). Q (W92 eq. 26,\n"
      "1/J^2 normalisation) is printed as it converges; it falls as N^-1/2.\n"
      "Deterministic for a seed and --threads when --rays is used (not with --time).\n"
      "--in-plane: instead, a direct estimate of rho in the plane of incidence (cones of --cone\n"
      "around theta_r every 2.5 deg; --isotropic turns the plane to all azimuths), optionally\n"
      "with He 1991 / Beckmann-Smith references and an SH file overlaid.\n"
      "Scene format: docs/westin.md; examples in examples/scenes/.\n\n"
      "Examples:\n"
      "  microbrdf simulate examples/scenes/westin_fig6.json --lmax 15 --time 60s -o w.shbrdf\n"
      "  microbrdf simulate examples/scenes/cylinders.json --rays 4000000 --seed 2 -o c.shbrdf "
      "--json\n"
      "  microbrdf simulate examples/scenes/westin_fig6.json --in-plane 0,30,45,60,75 "
      "--isotropic --he-sigma 10um --he-tau 65um --single-scatter --plot fig6.png");
  c->add_option("scene", a->scene, "Micro-scene JSON file")->required();
  c->add_option("-o,--output", a->output, "Output .shbrdf file");
  c->add_option("--lmax", a->lmax, "Highest SH order l (matrix size lmax(lmax+1)/2 squared)")
      ->capture_default_str()
      ->check(count_in(1, 64));
  auto* rays = c->add_option("--rays", a->rays, "Incident rays in all (N_i N_p)")
                   ->capture_default_str()
                   ->check(count_in(1, kMaxSamples, kWhySamples));
  c->add_option("--time", a->time, "Run for this long instead (e.g. 60s, 2min); not deterministic")
      ->excludes(rays);
  c->add_option("--points", a->points, "N_p: target points per incident direction")
      ->capture_default_str()
      ->check(count_in(1, 1e9));
  c->add_option("--branches", a->branches, "N_b: rays spawned at the first diffuse event")
      ->capture_default_str()
      ->check(count_in(1, 1e6));
  c->add_option("--max-depth", a->max_depth,
                "Scattering events before a path is cut (energy cut is reported)")
      ->capture_default_str()
      ->check(count_in(1, 1e4));
  c->add_option("--seed", a->seed, "Random seed")->capture_default_str();
  c->add_option("--threads", a->threads, "Threads (0 = all cores)")->capture_default_str();
  c->add_flag("--independent", a->independent,
              "Independent uniform incident directions (default: stratified in rounds of 1024)");
  c->add_option("--in-plane", a->in_plane, "Direct in-plane mode: theta_i list, e.g. 0,30,45,60,75")
      ->check(angle_in(0, 89.9 * M_PI / 180, true));
  c->add_option("--gonio-rays", a->gonio_rays, "--in-plane: rays per incident angle")
      ->capture_default_str()
      ->check(count_in(1, kMaxSamples, kWhySamples));
  c->add_option("--cone", a->cone, "--in-plane: half-angle of the exit cones")
      ->capture_default_str()
      ->check(angle_in(0, 20 * M_PI / 180));
  c->add_option("--phi-i", a->phi_i,
                "--in-plane: azimuth of the plane of incidence (light at phi + 180 deg)")
      ->capture_default_str()
      ->check(direction());
  c->add_flag("--isotropic", a->isotropic,
              "--in-plane: the scene is statistically isotropic; turn the plane of incidence to "
              "all azimuths (averages out one realisation's anisotropy)");
  c->add_flag("--single-scatter", a->single, "--in-plane: also the one-bounce part");
  c->add_option("--he-sigma", a->he_sigma,
                "--in-plane: reference surface rms height (He 1991 and Beckmann-Smith, with the "
                "Fresnel term of the height field's mirror material)")
      ->check(height());
  c->add_option("--he-tau", a->he_tau, "--in-plane: reference correlation length (He 1991)")
      ->check(distance());
  c->add_option("--sh", a->sh, "--in-plane: overlay this .shbrdf");
  c->add_option("--plot", a->plot, "--in-plane: figure, one panel per theta_i (.png/.svg)");
  c->add_option("--csv", a->csv, "--in-plane: CSV of every point (default: CSV on stdout)");
  c->add_flag("--visibility", a->visibility,
              "Instead: ray-traced visible fraction G1 and free travel probability from the mean "
              "plane vs polar angle (0..88 deg), with Smith and Sun 2002 for --he-sigma/--he-tau");
  c->add_option("--visibility-samples", a->vis_samples, "--visibility: samples per angle")
      ->capture_default_str()
      ->check(count_in(1, kMaxSamples, kWhySamples));
  c->add_flag("--json", a->json, "Print a summary as JSON on stdout");
  c->add_flag("-q,--quiet", a->quiet, "No progress on stderr");
  c->callback([a] { run_guarded("simulate", [&] { run(*a); }); });
}

}  // namespace microbrdf::cli
