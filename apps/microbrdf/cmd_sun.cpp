// `microbrdf sun ftp|simulate-ftp|slice`: Sun 2002's free travel probability (analytic and
// simulated as in the paper's section 4, compared with Smith: cmd_sun_simulate.cpp) and slices of
// its analytic BRDF.
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>

#include "cli_common.hpp"
#include "commands.hpp"
#include "microbrdf/brdf_slice.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/plot.hpp"
#include "microbrdf/sun2002.hpp"
#include "microbrdf/units.hpp"
#include "sun_common.hpp"

namespace microbrdf::cli {
namespace sun_cli {

namespace sun = microbrdf::sun2002;

// Radians to degrees for printing, rounded to 1e-9 deg (29.999999999999996 -> 30).
double deg(double rad) { return std::round(rad / kDeg * 1e9) / 1e9; }

std::vector<double> theta_grid(const SunArgs& a) {
  const double step = parse_angle(a.theta_step), tmax = parse_angle(a.theta_max);
  if (!(step > 0) || step > M_PI / 2) throw InputError("--theta-step must be in (0, 90] deg");
  if (!(tmax > 0) || tmax > M_PI / 2 + 1e-12)
    throw InputError("--theta-max must be in (0, 90] deg");
  std::vector<double> t;
  for (int i = 0;; ++i) {
    double v = i * step;
    if (v > tmax + 1e-9) break;
    t.push_back(std::min(v, M_PI / 2));
  }
  return t;
}

void check_s_list(const std::vector<double>& s) {
  if (s.empty()) throw InputError("--s: give at least one smoothness value tau/sigma");
  for (double v : s)
    if (!(v > 0) || !std::isfinite(v)) throw InputError("--s: smoothness values must be positive");
}

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.8g", v);
  return b;
}

std::string s_label(double s) {
  char b[32];
  std::snprintf(b, sizeof b, "s = %g", s);
  return b;
}

void add_s(CLI::App* c, SunArgs& a, bool list) {
  auto* o =
      c->add_option("--s", a.s,
                    list ? "Smoothness tau/sigma, one value or a list: 0.5 or 0.1,0.25,0.5,1,2,5"
                         : "Smoothness tau/sigma (correlation length / rms height)");
  o->required()->check(positive_number(1e3));  // s = 1e3 is a mirror to double precision
  if (list) o->delimiter(',');
}

}  // namespace sun_cli

namespace {
using namespace sun_cli;
namespace sun = microbrdf::sun2002;

void run_ftp(const SunArgs& a) {
  check_plot_name("--plot", a.plot);
  check_s_list(a.s);
  const auto theta = theta_grid(a);
  std::ostringstream csv;
  csv << "s,theta_deg,gamma0_sun,smith_g1,smith_mean_plane\n";
  Plot p;
  p.title = "Sun 2002 free travel probability (eq. 3.4.23)";
  p.x.label = "polar angle θ (deg)";
  p.y.label = "probability (1)";
  nlohmann::json curves = nlohmann::json::array();
  for (std::size_t si = 0; si < a.s.size(); ++si) {
    const double s = a.s[si];
    PlotSeries sunc, smith;
    sunc.label = "Γ₀, " + s_label(s) + (a.k_tau != 1 ? ", kτ = " + num(a.k_tau) : "");
    smith.label = a.s.size() == 1 ? "Smith G1 (Beckmann α = 2/s)" : "";
    smith.style = PlotStyle::Dashed;
    sunc.color = smith.color = plot_palette(si);
    nlohmann::json rows = nlohmann::json::array();
    for (double t : theta) {
      const double g = sun::ftp(t, s, a.k_tau), g1 = sun::smith_g1(t, s),
                   g0 = sun::smith_at_mean_plane(t, s);
      csv << num(s) << ',' << num(t / kDeg) << ',' << num(g) << ',' << num(g1) << ',' << num(g0)
          << '\n';
      rows.push_back(
          {{"theta_deg", deg(t)}, {"gamma0_sun", g}, {"smith_g1", g1}, {"smith_mean_plane", g0}});
      sunc.x.push_back(t / kDeg);
      sunc.y.push_back(g);
      smith.x.push_back(t / kDeg);
      smith.y.push_back(g1);
    }
    curves.push_back({{"s", s}, {"k_tau", a.k_tau}, {"points", rows}});
    p.add(sunc);
    p.add(smith);
  }
  if (a.s.size() > 1) {  // one legend entry for all dashed curves
    PlotSeries key({NAN}, {NAN}, "Smith G1 (dashed)", PlotStyle::Dashed);
    key.color = PlotColor{0.3, 0.3, 0.3};
    p.add(key);
  }
  if (!a.output.empty()) emit_text(a.output, csv.str());
  if (!a.plot.empty()) p.write(a.plot);
  if (a.json) {
    print_json({{"command", "sun ftp"}, {"equation", "Sun 2002 eq. 3.4.23"}, {"curves", curves}});
  } else if (a.output.empty()) {
    emit_text("-", csv.str());
  }
}

void run_slice(const SunArgs& a) {
  check_plot_name("--plot", a.plot);
  if (a.s.size() != 1) throw InputError("slice: give one --s value");
  const double s = a.s[0];
  check_s_list(a.s);
  const double ti = parse_angle(a.theta_i);
  if (!(ti >= 0 && ti < M_PI / 2)) throw InputError("--theta-i must be in [0, 90) deg");
  // The material's Fresnel term; without one R = 1 (Sun's upper bound for energy checks).
  MaterialSpec perfect;
  perfect.form = MaterialSpec::Form::Perfect;
  const MaterialSpec mat = material_spec(a.material, perfect);
  const bool have_fresnel = mat.form != MaterialSpec::Form::Perfect;
  const auto fresnel = have_fresnel ? make_fresnel(mat) : nullptr;
  const Fresnel* F = fresnel.get();
  constexpr double kLambda = 555e-9;  // the wavelength of the Fresnel term
  const double step = parse_angle(a.theta_step);
  if (!(step > 0) || step > M_PI / 4) throw InputError("--theta-step must be in (0, 45] deg");

  // The slice convention of every slice (brdf_slice.hpp): light at azimuth 180 deg, theta_o
  // signed with the mirror direction at +theta_i.
  const Vec3 wi = slice_light(ti);
  std::ostringstream csv;
  csv << "theta_o_deg,brdf_as_published,brdf_standard,published_over_standard,fresnel,gamma0_i,"
         "gamma0_o\n";
  PlotSeries pub, stdf;
  pub.label = "eq. 3.5.3 as published";
  stdf.label = "standard microfacet form";
  stdf.style = PlotStyle::Dashed;
  double peak_pub = 0, peak_std = 0, at_pub = 0, at_std = 0;
  const int n = static_cast<int>(std::floor((M_PI / 2) / step + 1e-9));
  for (int i = -n; i <= n; ++i) {
    const double to = i * step;
    if (std::abs(to) >= M_PI / 2 - 1e-12) continue;  // at the horizon the BRDF is 0
    const Vec3 wo = slice_view(ti, to, SlicePlane::In);
    const double fp = sun::brdf(wi, wo, s, sun::BrdfForm::AsPublished, F, kLambda);
    const double fs = sun::brdf(wi, wo, s, sun::BrdfForm::Standard, F, kLambda);
    const double cd = wi.dot((wi + wo).normalized());
    csv << num(to / kDeg) << ',' << num(fp) << ',' << num(fs) << ','
        << num(sun::published_over_standard(wi, wo)) << ',' << num(F ? F->eval(cd, kLambda) : 1.0)
        << ',' << num(sun::ftp(ti, s)) << ',' << num(sun::ftp(std::abs(to), s)) << '\n';
    pub.x.push_back(to / kDeg);
    pub.y.push_back(fp);
    stdf.x.push_back(to / kDeg);
    stdf.y.push_back(fs);
    if (fp > peak_pub) peak_pub = fp, at_pub = to;
    if (fs > peak_std) peak_std = fs, at_std = to;
  }
  Plot p;
  char title[160];
  std::snprintf(title, sizeof title, "Sun 2002 BRDF, plane of incidence: s = %g, θi = %g°, ", s,
                ti / kDeg);
  p.title = title + mat.describe();
  p.x.label = "viewing angle θo (deg; mirror direction at +θi)";
  p.y.label = "BRDF (1/sr)";
  if (a.log_y) p.y.scale = AxisScale::Log;
  p.add(pub);
  p.add(stdf);
  if (!a.output.empty()) emit_text(a.output, csv.str());
  if (!a.plot.empty()) p.write(a.plot);
  if (a.json) {
    print_json({{"command", "sun slice"},
                {"s", s},
                {"theta_i_deg", deg(ti)},
                {"fresnel", have_fresnel ? mat.to_json() : nlohmann::json("R = 1")},
                {"albedo_as_published", sun::albedo(ti, s, sun::BrdfForm::AsPublished, F, kLambda)},
                {"albedo_standard", sun::albedo(ti, s, sun::BrdfForm::Standard, F, kLambda)},
                {"peak_as_published", {{"value", peak_pub}, {"theta_o_deg", deg(at_pub)}}},
                {"peak_standard", {{"value", peak_std}, {"theta_o_deg", deg(at_std)}}}});
  } else if (a.output.empty()) {
    emit_text("-", csv.str());
  }
}

}  // namespace

void register_sun(CLI::App& app) {
  auto a = std::make_shared<SunArgs>();
  auto* sunc = app.add_subcommand(
      "sun", "Sun 2002: free travel probability (analytic, simulated, Smith) and BRDF");
  sunc->require_subcommand(1);
  sunc->footer(
      "Surface: Gaussian heights (rms sigma), correlation exp(-r^2/tau^2), smoothness s = "
      "tau/sigma\n"
      "(Beckmann alpha = 2/s). See docs/sun2002.md.\n\n"
      "Examples:\n"
      "  microbrdf sun ftp --s 0.5 --theta-step 1deg -o curve.csv --plot ftp.png\n"
      "  microbrdf sun simulate-ftp --s 0.1,0.25,0.5,1,2,5 --samples 100000 --seed 1 -o sim.csv "
      "--plot fig7.png\n"
      "Slices: the light at azimuth 180 deg, theta_o signed with the mirror direction at\n"
      "+theta_i (the convention of `brdf slice`).\n"
      "  microbrdf sun slice --s 2 --theta-i 30deg --n 0.2 --k 3.0 -o slice.csv --plot slice.png");

  auto* f = sunc->add_subcommand(
      "ftp", "Gamma_0(theta; s) of eq. 3.4.23 with Smith's G1 for the same surface");
  add_s(f, *a, true);
  f->add_option("--theta-step", a->theta_step, "Angle step")
      ->capture_default_str()
      ->check(angle_in(0, M_PI / 2));
  f->add_option("--k-tau", a->k_tau, "Sun's heuristic constant k tau (eq. 3.4.21 sets 1)")
      ->capture_default_str();
  f->add_option("-o,--output", a->output, "CSV file (default: CSV on stdout)");
  f->add_option("--plot", a->plot, "Also draw the curves (.png or .svg)");
  f->add_flag("--json", a->json, "Print the curves as JSON on stdout");
  f->callback([a] { run_guarded("sun", [&] { run_ftp(*a); }); });

  auto* m = sunc->add_subcommand(
      "simulate-ftp",
      "Sun's section 4 experiment: rays from zero crossings of generated Gaussian profiles");
  add_s(m, *a, true);
  m->add_option("--samples", a->samples,
                "Zero crossings per s (each casts a ray both ways at every angle)")
      ->capture_default_str()
      ->check(count_in(1, 1e9, "each crossing casts rays at every angle; 1e9 takes hours"));
  m->add_option("--seed", a->seed, "Random seed (same seed, same result)")->capture_default_str();
  m->add_option("--theta-step", a->theta_step, "Angle step (90 deg is exactly 0, not simulated)")
      ->capture_default_str()
      ->check(angle_in(0, M_PI / 2));
  m->add_option("--theta-max", a->theta_max, "Largest angle")
      ->capture_default_str()
      ->check(angle_in(0, M_PI / 2));
  m->add_option("--samples-per-tau", a->samples_per_tau, "Profile samples per correlation length")
      ->capture_default_str()
      ->check(positive_number(1e3));
  m->add_option("--profile-length", a->profile_length, "Samples per profile holding crossings")
      ->capture_default_str()
      ->check(count_in(16, 1e8));
  m->add_option("-o,--output", a->output, "CSV file of every (s, theta) point");
  m->add_option("--plot", a->plot, "Figure like Sun's Fig. 7, all s in one panel (.png or .svg)");
  m->add_option("--plot-grid", a->plot_grid, "One panel per s, with Smith at h = 0 and error bars");
  m->add_flag("--json", a->json, "Print the agreement summary as JSON on stdout");
  m->callback([a] { run_guarded("sun", [&] { run_simulate(*a); }); });

  auto* sl = sunc->add_subcommand(
      "slice", "The analytic BRDF (eq. 3.5.3) in the plane of incidence, both forms");
  add_s(sl, *a, false);
  sl->add_option("--theta-i", a->theta_i, "Polar angle of the light")
      ->capture_default_str()
      ->check(polar_angle());
  sl->add_option("--theta-step", a->theta_step, "Viewing angle step")
      ->capture_default_str()
      ->check(angle_in(0, M_PI / 4));
  add_material_flags(sl, a->material, "default: R = 1");
  sl->add_flag("--log", a->log_y, "Logarithmic BRDF axis in the plot");
  sl->add_option("-o,--output", a->output, "CSV file (default: CSV on stdout)");
  sl->add_option("--plot", a->plot, "Also draw the slice (.png or .svg)");
  sl->add_flag("--json", a->json, "Print a summary (peaks, albedos) as JSON on stdout");
  sl->callback([a] { run_guarded("sun", [&] { run_slice(*a); }); });
}

}  // namespace microbrdf::cli
