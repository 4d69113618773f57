// `microbrdf simulate SCENE.json`: Westin 1992 SH-matrix BRDF by Monte Carlo ray tracing of a
// micro-scene (Embree), and a direct in-plane "goniometer" mode compared with He 1991 /
// Beckmann-Smith.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>

#include "cli_common.hpp"
#include "cli_threads.hpp"
#include "commands.hpp"
#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/plot.hpp"
#include "microbrdf/simulate.hpp"
#include "microbrdf/sun2002.hpp"
#include "microbrdf/units.hpp"

namespace microbrdf::cli {
namespace {

constexpr double kDeg = M_PI / 180;

struct SimArgs {
  std::string scene, output, time = "", in_plane, cone = "4deg", he_sigma, he_tau, sh, plot, csv;
  std::string phi_i = "0deg";
  bool isotropic = false, visibility = false;
  std::uint64_t vis_samples = 40000;
  int lmax = 15, points = 16, branches = 1, max_depth = 100, threads = 0;
  std::uint64_t rays = 2000000, seed = 1, gonio_rays = 1000000;
  bool json = false, quiet = false, single = false, independent = false;
};

double parse_seconds(const std::string& t) {
  std::size_t pos = 0;
  double v = 0;
  try {
    v = std::stod(t, &pos);
  } catch (const std::exception&) {
    throw InputError("--time: expected e.g. 60s, 2min or 1h (got '" + t + "')");
  }
  std::string unit = t.substr(pos);
  while (!unit.empty() && unit.front() == ' ') unit.erase(0, 1);
  if (unit.empty() || unit == "s") return v;
  if (unit == "min" || unit == "m") return 60 * v;
  if (unit == "h") return 3600 * v;
  throw InputError("--time: unknown unit '" + unit + "' (s, min or h)");
}

std::vector<double> angle_list(const std::string& text) {
  std::vector<double> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(parse_angle(item));
  if (out.empty()) throw InputError("--in-plane: give angles such as 0,30,45,60,75");
  for (double a : out)
    if (!(a >= 0 && a < M_PI / 2)) throw InputError("--in-plane: angles must be in [0, 90) deg");
  return out;
}

TraceOptions trace_options(const SimArgs& a) {
  TraceOptions t;
  t.branches = a.branches;
  t.max_depth = a.max_depth;
  if (a.branches < 1 || a.branches > kMaxBranches)
    throw InputError("--branches must lie in 1.." + std::to_string(kMaxBranches));
  if (a.max_depth < 1) throw InputError("--max-depth must be >= 1");
  return t;
}

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
  if (!a.quiet)
    o.progress = [](std::uint64_t dirs, std::uint64_t rays, double t, double q) {
      std::fprintf(stderr,
                   "microbrdf simulate: %llu directions, %.3g rays, %.1f s, %.3g rays/s, Q = "
                   "%.3g\n",
                   static_cast<unsigned long long>(dirs), double(rays), t,
                   t > 0 ? double(rays) / t : 0.0, q);
    };
  SimulateStats st;
  const ShEstimator est = simulate(scene, o, &st);
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

void run_in_plane(const SimArgs& a, const MicroScene& scene) {
  const auto thetas = angle_list(a.in_plane);
  const double half = parse_angle(a.cone);
  if (!(half > 0 && half < 20 * kDeg)) throw InputError("--cone must be in (0, 20) deg");
  const bool ref = !a.he_sigma.empty() || !a.he_tau.empty();
  double sigma = 0, tau = 0;
  if (ref) {
    if (a.he_sigma.empty() || a.he_tau.empty())
      throw InputError("--he-sigma and --he-tau go together");
    sigma = parse_length(a.he_sigma);
    tau = parse_length(a.he_tau);
  }
  std::unique_ptr<ShBrdf> sh;
  if (!a.sh.empty()) sh = std::make_unique<ShBrdf>(ShBrdf::load(a.sh));
  // The references use the Fresnel term of the first height field's mirror material (F = 1
  // otherwise), at the half-vector angle, as the microfacet facets see it.
  std::shared_ptr<const Fresnel> fresnel;
  for (const auto& hf : scene.desc().heightfields) {
    const MicroMaterial& m = scene.desc().materials[hf.material];
    if (m.kind == MicroMaterial::Kind::mirror) fresnel = m.fresnel;
    break;
  }
  std::unique_ptr<MicrofacetBrdf> smith;
  if (ref)
    smith = std::make_unique<MicrofacetBrdf>(
        std::make_shared<BeckmannDistribution>(2 * sigma / tau),
        fresnel ? fresnel : std::make_shared<const PerfectMirrorFresnel>());
  const double lambda = scene.desc().wavelength_m;
  // The plane of incidence at azimuth phi_i: light at phi_i + 180 deg, theta_r > 0 towards phi_i.
  const double phi = parse_angle(a.phi_i), cp = std::cos(phi), sp = std::sin(phi);
  std::vector<double> tr;
  std::vector<Eigen::Vector3d> dirs;
  for (double t = -85; t <= 85 + 1e-9; t += 2.5) {
    if (std::abs(t) * kDeg + half >= M_PI / 2) continue;
    tr.push_back(t);
    dirs.emplace_back(cp * std::sin(t * kDeg), sp * std::sin(t * kDeg), std::cos(t * kDeg));
  }
  // Cosine-weighted cone average of a model (what the simulation measures).
  auto cone_avg = [&](auto&& f, const Eigen::Vector3d& c) {
    const Eigen::Vector3d t1 = Eigen::Vector3d(-sp, cp, 0).cross(c).normalized(), t2 = c.cross(t1);
    double num = 0, den = 0;
    for (int i = 0; i < 6; ++i) {
      const double r = (i + 0.5) / 6 * half;
      for (int k = 0; k < 16; ++k) {
        const double ph = 2 * M_PI * k / 16;
        const Eigen::Vector3d w =
            std::cos(r) * c + std::sin(r) * (std::cos(ph) * t1 + std::sin(ph) * t2);
        num += std::sin(r) * w.z() * f(w);
        den += std::sin(r) * w.z();
      }
    }
    return num / den;
  };
  nlohmann::json out = nlohmann::json::array();
  std::vector<Plot> plots;
  std::ostringstream csv;
  csv << "theta_i_deg,theta_r_deg,simulated,simulated_single,he1991,beckmann_smith,sh\n";
  for (std::size_t ia = 0; ia < thetas.size(); ++ia) {
    const double ti = thetas[ia];
    const Eigen::Vector3d wi(-cp * std::sin(ti), -sp * std::sin(ti), std::cos(ti));
    TraceCounters c;
    const auto sim = cap_brdf(scene, wi, dirs, half, a.gonio_rays, trace_options(a), a.seed + ia,
                              &c, a.isotropic);
    std::vector<double> single;
    if (a.single) {
      TraceOptions t1 = trace_options(a);
      t1.max_depth = 1;
      single = cap_brdf(scene, wi, dirs, half, a.gonio_rays, t1, a.seed + ia, nullptr, a.isotropic);
    }
    std::vector<double> he, sm, shv;
    for (std::size_t k = 0; k < dirs.size(); ++k) {
      if (ref) {
        he.push_back(cone_avg(
            [&](const Eigen::Vector3d& w) {
              return he1991_geometric_brdf(wi, w, sigma, tau, true, fresnel.get(), lambda);
            },
            dirs[k]));
        sm.push_back(cone_avg([&](const Eigen::Vector3d& w) { return smith->eval(wi, w, lambda); },
                              dirs[k]));
      }
      if (sh) shv.push_back(sh->eval(wi, dirs[k], lambda));
    }
    auto at = [](const std::vector<double>& v, std::size_t k) {
      return v.empty() ? std::string() : std::to_string(v[k]);
    };
    for (std::size_t k = 0; k < dirs.size(); ++k)
      csv << ti / kDeg << "," << tr[k] << "," << sim[k] << "," << at(single, k) << "," << at(he, k)
          << "," << at(sm, k) << "," << at(shv, k) << "\n";
    out.push_back({{"theta_i_deg", ti / kDeg},
                   {"theta_r_deg", tr},
                   {"simulated", sim},
                   {"simulated_single", single},
                   {"he1991", he},
                   {"beckmann_smith", sm},
                   {"sh", shv},
                   {"albedo", c.energy_out / double(c.incident_rays)},
                   {"energy_below", c.energy_down / double(c.incident_rays)}});
    if (!a.quiet)
      std::fprintf(stderr, "microbrdf simulate: theta_i = %.0f deg done (albedo %.4f)\n", ti / kDeg,
                   c.energy_out / double(c.incident_rays));
    Plot p;
    p.title = "theta_i = " + std::to_string(int(std::lround(ti / kDeg))) + " deg" +
              (phi != 0 ? ", plane at phi " + std::to_string(int(std::lround(phi / kDeg))) + " deg"
                        : std::string());
    p.x.label = "theta_r (deg), + = forward";
    p.y.label = "BRDF (1/sr)";
    p.x.min = -90;
    p.x.max = 90;
    p.y.min = 0;
    PlotSeries s(tr, sim, "ray traced", PlotStyle::Markers);
    p.add(s);
    if (a.single)
      p.add(PlotSeries(tr, single, "ray traced, 1 bounce", PlotStyle::Markers)).marker =
          MarkerShape::Triangle;
    if (ref) {
      p.add(PlotSeries(tr, he, "He 1991 (geom. limit)", PlotStyle::Dashed));
      p.add(PlotSeries(tr, sm, "Beckmann + Smith", PlotStyle::Dotted));
    }
    if (sh) p.add(PlotSeries(tr, shv, "SH matrix (lmax " + std::to_string(sh->lmax()) + ")"));
    plots.push_back(std::move(p));
  }
  if (!a.csv.empty()) write_file_atomic(a.csv, csv.str());
  if (!a.plot.empty())
    write_plot_grid(plots, plots.size() > 3 ? 3 : plots.size(), a.plot, 480, 360);
  if (a.json)
    print_json({{"scene", a.scene}, {"cone_half_angle_deg", half / kDeg}, {"curves", out}});
  else if (a.csv.empty())
    std::fputs(csv.str().c_str(), stdout);
}

// Ray-traced G1 and free travel probability against Smith and Sun 2002 (theory notes 2, 5).
void run_visibility(const SimArgs& a, const MicroScene& scene) {
  const bool ref = !a.he_sigma.empty() && !a.he_tau.empty();
  const double sigma = ref ? parse_length(a.he_sigma) : 0, tau = ref ? parse_length(a.he_tau) : 0;
  std::vector<double> th, g1, g1e, ftp, ftpe, smith, sun, smith0;
  std::ostringstream csv;
  csv << "theta_deg,g1_traced,g1_std_error,ftp_traced,ftp_std_error,smith_g1,sun_gamma0,"
         "smith_mean_plane\n";
  const double band = ref ? 0.05 * sigma : 0.01 * (scene.zmax() - scene.zmin());
  for (double t = 0; t <= 88 + 1e-9; t += 4) {
    const double r = t * kDeg;
    const auto g = visible_fraction(scene, r, a.vis_samples, a.seed);
    const auto f = free_travel_probability(scene, r, band, a.vis_samples, a.seed + 1);
    th.push_back(t);
    g1.push_back(g.value);
    g1e.push_back(g.std_error);
    ftp.push_back(f.value);
    ftpe.push_back(f.std_error);
    if (ref) {
      smith.push_back(sun2002::smith_g1(r, tau / sigma));
      sun.push_back(sun2002::ftp(r, tau / sigma));
      smith0.push_back(sun2002::smith_at_mean_plane(r, tau / sigma));
    }
    csv << t << "," << g.value << "," << g.std_error << "," << f.value << "," << f.std_error;
    if (ref) csv << "," << smith.back() << "," << sun.back() << "," << smith0.back();
    csv << "\n";
  }
  if (!a.csv.empty()) write_file_atomic(a.csv, csv.str());
  if (!a.plot.empty()) {
    Plot p;
    p.title = "Visibility on " + scene.desc().name;
    p.x.label = "polar angle (deg)";
    p.y.label = "fraction";
    p.x.min = 0;
    p.x.max = 90;
    p.y.min = 0;
    p.y.max = 1.05;
    auto& s1 = p.add(PlotSeries(th, g1, "visible fraction G1 (traced)", PlotStyle::Markers));
    s1.y_err = g1e;
    auto& s2 = p.add(PlotSeries(th, ftp, "free travel from z = 0 (traced)", PlotStyle::Markers));
    s2.y_err = ftpe;
    s2.marker = MarkerShape::Triangle;
    if (ref) {
      p.add(PlotSeries(th, smith, "Smith G1 = 1/(1+Lambda)"));
      p.add(PlotSeries(th, sun, "Sun Gamma_0 (eq. 3.4.23)", PlotStyle::Dashed));
      p.add(PlotSeries(th, smith0, "Smith at z = 0: 2^-Lambda", PlotStyle::Dotted));
    }
    p.write(a.plot);
  }
  if (a.json)
    print_json({{"theta_deg", th},
                {"g1_traced", g1},
                {"g1_std_error", g1e},
                {"ftp_traced", ftp},
                {"ftp_std_error", ftpe},
                {"smith_g1", smith},
                {"sun_gamma0", sun},
                {"smith_mean_plane", smith0}});
  else if (a.csv.empty())
    std::fputs(csv.str().c_str(), stdout);
}

void run(const SimArgs& a) {
  MicroScene scene(load_micro_scene(a.scene));
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
      "edge effects. Exits feed the estimator of theory 6.4 (W92 eqs. 17, 25); the matrix is\n"
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
      ->capture_default_str();
  auto* rays =
      c->add_option("--rays", a->rays, "Incident rays in all (N_i N_p)")->capture_default_str();
  c->add_option("--time", a->time, "Run for this long instead (e.g. 60s, 2min); not deterministic")
      ->excludes(rays);
  c->add_option("--points", a->points, "N_p: target points per incident direction")
      ->capture_default_str();
  c->add_option("--branches", a->branches, "N_b: rays spawned at the first diffuse event")
      ->capture_default_str();
  c->add_option("--max-depth", a->max_depth,
                "Scattering events before a path is cut (energy cut is reported)")
      ->capture_default_str();
  c->add_option("--seed", a->seed, "Random seed")->capture_default_str();
  c->add_option("--threads", a->threads, "Threads (0 = all cores)")->capture_default_str();
  c->add_flag("--independent", a->independent,
              "Independent uniform incident directions (default: stratified in rounds of 1024)");
  c->add_option("--in-plane", a->in_plane,
                "Direct in-plane mode: theta_i list, e.g. 0,30,45,60,75");
  c->add_option("--gonio-rays", a->gonio_rays, "--in-plane: rays per incident angle")
      ->capture_default_str();
  c->add_option("--cone", a->cone, "--in-plane: half-angle of the exit cones")
      ->capture_default_str();
  c->add_option("--phi-i", a->phi_i,
                "--in-plane: azimuth of the plane of incidence (light at phi + 180 deg)")
      ->capture_default_str();
  c->add_flag("--isotropic", a->isotropic,
              "--in-plane: the scene is statistically isotropic; turn the plane of incidence to "
              "all azimuths (averages out one realisation's anisotropy)");
  c->add_flag("--single-scatter", a->single, "--in-plane: also the one-bounce part");
  c->add_option("--he-sigma", a->he_sigma,
                "--in-plane: reference surface rms height (He 1991 and Beckmann-Smith, with the "
                "Fresnel term of the height field's mirror material)");
  c->add_option("--he-tau", a->he_tau, "--in-plane: reference correlation length (He 1991)");
  c->add_option("--sh", a->sh, "--in-plane: overlay this .shbrdf");
  c->add_option("--plot", a->plot, "--in-plane: figure, one panel per theta_i (.png/.svg)");
  c->add_option("--csv", a->csv, "--in-plane: CSV of every point (default: CSV on stdout)");
  c->add_flag("--visibility", a->visibility,
              "Instead: ray-traced visible fraction G1 and free travel probability from the mean "
              "plane vs polar angle (0..88 deg), with Smith and Sun 2002 for --he-sigma/--he-tau");
  c->add_option("--visibility-samples", a->vis_samples, "--visibility: samples per angle")
      ->capture_default_str();
  c->add_flag("--json", a->json, "Print a summary as JSON on stdout");
  c->add_flag("-q,--quiet", a->quiet, "No progress on stderr");
  c->callback([a] { run_guarded("simulate", [&] { run(*a); }); });
}

}  // namespace microbrdf::cli
