// `microbrdf sun simulate-ftp`: Sun 2002's section 4 experiment (sun2002::simulate_ftp) against
// the analytic free travel probability and Smith's masking (sun2002::compare_ftp), as CSV,
// figures and JSON.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "cli_common.hpp"
#include "microbrdf/plot.hpp"
#include "microbrdf/sun2002.hpp"
#include "sun_common.hpp"

namespace microbrdf::cli::sun_cli {

namespace sun = microbrdf::sun2002;

void run_simulate(const SunArgs& a) {
  check_plot_name("--plot", a.plot);
  check_plot_name("--plot-grid", a.plot_grid);
  check_s_list(a.s);
  const auto theta = theta_grid(a);
  std::ostringstream csv;
  csv << "s,theta_deg,gamma_sim_leaving,se_leaving,gamma_sim_any,se_any,rays,rays_leaving,free,"
         "gamma0_sun,"
         "smith_g1,smith_mean_plane\n";
  Plot fig;
  fig.title = "Free travel probability: simulation vs Sun eq. 3.4.23 vs Smith";
  fig.x.label = "polar angle θ (deg)";
  fig.y.label = "free travel probability (1)";
  std::vector<Plot> panels;
  nlohmann::json per_s = nlohmann::json::array();
  double total_rays = 0, total_sec = 0;
  for (std::size_t si = 0; si < a.s.size(); ++si) {
    const double s = a.s[si];
    progress("sun", si, a.s.size(), s_label(s));
    sun::FtpSimParams p;
    p.s = s;
    p.theta = theta;
    p.crossings = a.samples;
    p.seed = a.seed;
    p.samples_per_tau = a.samples_per_tau;
    p.profile_length = a.profile_length;
    const auto t0 = std::chrono::steady_clock::now();
    const auto r = sun::simulate_ftp(p);
    const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    total_sec += sec;

    PlotSeries analytic, smith, sim_l, sim_a, smith0;
    const PlotColor c = plot_palette(si);
    analytic.color = smith.color = sim_l.color = sim_a.color = smith0.color = c;
    smith.style = PlotStyle::Dashed;
    smith0.style = PlotStyle::Dotted;
    sim_l.style = sim_a.style = PlotStyle::Markers;
    sim_l.marker_size = sim_a.marker_size = 2.2;
    sim_a.marker = MarkerShape::Triangle;
    for (const auto& pt : r.points) {
      const double t = pt.theta;
      const double g = sun::ftp(t, s), g1 = sun::smith_g1(t, s),
                   g0 = sun::smith_at_mean_plane(t, s);
      const bool simulated = t < M_PI / 2 - 1e-12;
      csv << num(s) << ',' << num(t / kDeg) << ',' << num(pt.gamma_leaving) << ','
          << num(pt.se_leaving) << ',' << num(pt.gamma_any) << ',' << num(pt.se_any) << ','
          << pt.rays << ',' << pt.rays_leaving << ',' << pt.free << ',' << num(g) << ',' << num(g1)
          << ',' << num(g0) << '\n';
      analytic.x.push_back(t / kDeg);
      analytic.y.push_back(g);
      smith.x.push_back(t / kDeg);
      smith.y.push_back(g1);
      smith0.x.push_back(t / kDeg);
      smith0.y.push_back(g0);
      if (!simulated) continue;
      sim_l.x.push_back(t / kDeg);
      sim_l.y.push_back(pt.gamma_leaving);
      sim_l.y_err.push_back(pt.se_leaving);
      sim_a.x.push_back(t / kDeg);
      sim_a.y.push_back(pt.gamma_any);
      sim_a.y_err.push_back(pt.se_any);
    }
    const sun::FtpAgreement ag = sun::compare_ftp(r);
    total_rays += static_cast<double>(ag.rays);
    const auto dev = [](const sun::FtpDeviation& d) {
      return nlohmann::json{
          {"max_abs_diff", std::abs(d.diff)}, {"signed", d.diff}, {"at_theta_deg", deg(d.theta)}};
    };
    per_s.push_back({{"s", s},
                     {"profiles", r.profiles},
                     {"crossings", r.crossings},
                     {"excluded_crossings", r.excluded},
                     {"slope_rms", r.slope_rms},
                     {"slope_rms_expected", std::sqrt(2.0) / s},
                     {"max_standard_error_leaving", ag.max_standard_error_leaving},
                     {"leaving_minus_sun", dev(ag.leaving_minus_sun)},
                     {"leaving_minus_smith_g1", dev(ag.leaving_minus_smith_g1)},
                     {"leaving_minus_smith_mean_plane", dev(ag.leaving_minus_smith_mean_plane)},
                     {"any_minus_sun", dev(ag.any_minus_sun)},
                     {"best_k_tau_leaving", ag.best_k_tau_leaving},
                     {"best_k_tau_any", ag.best_k_tau_any},
                     {"seconds", sec},
                     {"rays", ag.rays}});
    if (!a.json)
      std::fprintf(stderr,
                   "microbrdf sun: s = %g: %zu crossings on %zu profiles; max |sim - Sun| = %.3f "
                   "at %.0f deg (rays leaving above), %.3f at %.0f deg (any crossing); max |sim - "
                   "Smith G1| = %.3f at %.0f deg; max |sim - Smith(h=0)| = %.3f at %.0f deg; max "
                   "s.e. %.4f; best k tau %.3g / %.3g; %.1f s\n",
                   s, r.crossings, r.profiles, std::abs(ag.leaving_minus_sun.diff),
                   ag.leaving_minus_sun.theta / kDeg, std::abs(ag.any_minus_sun.diff),
                   ag.any_minus_sun.theta / kDeg, std::abs(ag.leaving_minus_smith_g1.diff),
                   ag.leaving_minus_smith_g1.theta / kDeg,
                   std::abs(ag.leaving_minus_smith_mean_plane.diff),
                   ag.leaving_minus_smith_mean_plane.theta / kDeg, ag.max_standard_error_leaving,
                   ag.best_k_tau_leaving, ag.best_k_tau_any, sec);

    analytic.label = s_label(s);
    fig.add(analytic);
    fig.add(smith);
    {
      // All s in one panel: markers about every 3 deg keep it legible.
      const double step = theta.size() > 1 ? theta[1] - theta[0] : 1;
      const std::size_t every =
          std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(3 * kDeg / step)));
      PlotSeries l = sim_l, an = sim_a;
      l.x.clear(), l.y.clear(), l.y_err.clear(), an.x.clear(), an.y.clear(), an.y_err.clear();
      for (std::size_t i = 0; i < sim_l.x.size(); i += every) {
        l.x.push_back(sim_l.x[i]), l.y.push_back(sim_l.y[i]), l.y_err.push_back(sim_l.y_err[i]);
        an.x.push_back(sim_a.x[i]), an.y.push_back(sim_a.y[i]), an.y_err.push_back(sim_a.y_err[i]);
      }
      fig.add(l);
      fig.add(an);
    }

    Plot panel;
    panel.title = s_label(s);
    panel.x.label = "θ (deg)";
    panel.y.label = "probability (1)";
    panel.font_size = 11;
    analytic.label = "Sun Γ₀ (eq. 3.4.23)";
    smith.label = "Smith G1";
    smith0.label = "Smith, h = 0";
    sim_l.label = "sim., leaving above";
    sim_a.label = "sim., any crossing";
    panel.add(analytic);
    panel.add(smith);
    panel.add(smith0);
    panel.add(sim_l);
    panel.add(sim_a);
    panels.push_back(std::move(panel));
  }
  // Legend keys for the styles (the colours are labelled by the solid curves).
  const PlotColor grey{0.3, 0.3, 0.3};
  PlotSeries k1({NAN}, {NAN}, "Smith G1", PlotStyle::Dashed),
      k2({NAN}, {NAN}, "sim., leaving above", PlotStyle::Markers),
      k3({NAN}, {NAN}, "sim., any crossing", PlotStyle::Markers);
  k1.color = k2.color = k3.color = grey;
  k3.marker = MarkerShape::Triangle;
  fig.add(k1);
  fig.add(k2);
  fig.add(k3);

  if (!a.output.empty()) emit_text(a.output, csv.str());
  if (!a.plot.empty()) fig.write(a.plot, 900, 620);
  if (!a.plot_grid.empty())
    write_plot_grid(panels, std::min<std::size_t>(3, panels.size()), a.plot_grid, 420, 320);
  if (a.json)
    print_json({{"command", "sun simulate-ftp"},
                {"samples", a.samples},
                {"seed", a.seed},
                {"samples_per_tau", a.samples_per_tau},
                {"rays_per_second", total_sec > 0 ? total_rays / total_sec : 0},
                {"results", per_s}});
}

}  // namespace microbrdf::cli::sun_cli
