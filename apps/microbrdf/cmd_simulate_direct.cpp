// `microbrdf simulate --in-plane | --visibility`: the direct modes on a micro-scene, the virtual
// in-plane goniometer (Westin 1992 Fig. 6 against He 1991 and Beckmann-Smith) and the ray-traced
// visibility (Smith's G1, Sun 2002's free travel probability).
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>

#include "cli_common.hpp"
#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/goniometer.hpp"
#include "microbrdf/plot.hpp"
#include "microbrdf/sh_brdf.hpp"
#include "microbrdf/sun2002.hpp"
#include "microbrdf/units.hpp"
#include "simulate_args.hpp"

namespace microbrdf::cli::simulate_cli {

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

void run_in_plane(const SimArgs& a, const MicroScene& scene) {
  GoniometerOptions g;
  g.theta_i_rad = angle_list(a.in_plane);
  g.cone_half_angle_rad = parse_angle(a.cone);
  const double half = g.cone_half_angle_rad;
  if (!(half > 0 && half < 20 * kDeg)) throw InputError("--cone must be in (0, 20) deg");
  const bool ref = !a.he_sigma.empty() || !a.he_tau.empty();
  if (ref) {
    if (a.he_sigma.empty() || a.he_tau.empty())
      throw InputError("--he-sigma and --he-tau go together");
    g.he_sigma_m = parse_length(a.he_sigma);
    g.he_tau_m = parse_length(a.he_tau);
  }
  if (!a.sh.empty()) g.sh = std::make_shared<ShBrdf>(ShBrdf::load(a.sh));
  g.phi_i_rad = parse_angle(a.phi_i);
  g.rays = a.gonio_rays;
  g.trace = trace_options(a);
  g.seed = a.seed;
  g.isotropic = a.isotropic;
  g.single_scatter = a.single;
  const double phi = g.phi_i_rad;
  nlohmann::json out = nlohmann::json::array();
  std::vector<Plot> plots;
  std::ostringstream csv;
  csv << "theta_i_deg,theta_r_deg,simulated,simulated_single,he1991,beckmann_smith,sh\n";
  const auto curves = in_plane_goniometer(scene, g, [&](const GoniometerCurve& c) {
    if (!a.quiet)
      std::fprintf(stderr, "microbrdf simulate: theta_i = %.0f deg done (albedo %.4f)\n",
                   c.theta_i_rad / kDeg, c.albedo);
  });
  for (const auto& c : curves) {
    const double ti = c.theta_i_rad;
    const auto& tr = c.theta_r_deg;
    auto at = [](const std::vector<double>& v, std::size_t k) {
      return v.empty() ? std::string() : std::to_string(v[k]);
    };
    for (std::size_t k = 0; k < tr.size(); ++k)
      csv << ti / kDeg << "," << tr[k] << "," << c.simulated[k] << "," << at(c.simulated_single, k)
          << "," << at(c.he1991, k) << "," << at(c.beckmann_smith, k) << "," << at(c.sh, k) << "\n";
    out.push_back({{"theta_i_deg", ti / kDeg},
                   {"theta_r_deg", tr},
                   {"simulated", c.simulated},
                   {"simulated_single", c.simulated_single},
                   {"he1991", c.he1991},
                   {"beckmann_smith", c.beckmann_smith},
                   {"sh", c.sh},
                   {"albedo", c.albedo},
                   {"energy_below", c.energy_below}});
    Plot p;
    p.title = "theta_i = " + std::to_string(int(std::lround(ti / kDeg))) + " deg" +
              (phi != 0 ? ", plane at phi " + std::to_string(int(std::lround(phi / kDeg))) + " deg"
                        : std::string());
    p.x.label = "theta_r (deg), + = forward";
    p.y.label = "BRDF (1/sr)";
    p.x.min = -90;
    p.x.max = 90;
    p.y.min = 0;
    p.add(PlotSeries(tr, c.simulated, "ray traced", PlotStyle::Markers));
    if (a.single)
      p.add(PlotSeries(tr, c.simulated_single, "ray traced, 1 bounce", PlotStyle::Markers)).marker =
          MarkerShape::Triangle;
    if (ref) {
      p.add(PlotSeries(tr, c.he1991, "He 1991 (geom. limit)", PlotStyle::Dashed));
      p.add(PlotSeries(tr, c.beckmann_smith, "Beckmann + Smith", PlotStyle::Dotted));
    }
    if (g.sh) p.add(PlotSeries(tr, c.sh, "SH matrix (lmax " + std::to_string(g.sh->lmax()) + ")"));
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

// Ray-traced G1 and free travel probability against Smith and Sun 2002 (docs/theory.md §2, 5).
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

}  // namespace microbrdf::cli::simulate_cli
