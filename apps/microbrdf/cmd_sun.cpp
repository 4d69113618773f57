// `microbrdf sun ftp|simulate-ftp|slice`: Sun 2002's free travel probability (analytic and
// simulated as in the paper's section 4, compared with Smith) and slices of its analytic BRDF.
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>

#include "cli_common.hpp"
#include "commands.hpp"
#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/plot.hpp"
#include "microbrdf/sun2002.hpp"
#include "microbrdf/units.hpp"

namespace microbrdf::cli {
namespace {

namespace sun = microbrdf::sun2002;
constexpr double kDeg = M_PI / 180;

// Radians to degrees for printing, rounded to 1e-9 deg (29.999999999999996 -> 30).
double deg(double rad) { return std::round(rad / kDeg * 1e9) / 1e9; }

struct SunArgs {
  std::vector<double> s;
  std::string theta_step = "1deg", theta_max = "90deg", theta_i = "30deg";
  std::string output, plot, plot_grid;
  bool json = false, log_y = false;
  double k_tau = 1;
  std::size_t samples = 100000;
  std::uint64_t seed = 1;
  double samples_per_tau = 16;
  std::size_t profile_length = 65536;
  double n = NAN, k = NAN;
};

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

// Writes CSV text to `path` atomically, or to stdout when path is "-".
void emit_csv(const std::string& path, const std::string& text) {
  if (path == "-") {
    std::fwrite(text.data(), 1, text.size(), stdout);
    return;
  }
  write_file_atomic(path, text);
}

// Least-squares k_tau for Gamma_0(theta; s, k_tau) against simulated values (golden section on
// log k over [0.01, 100]).
double fit_k_tau(double s, const std::vector<double>& theta, const std::vector<double>& g) {
  auto cost = [&](double lk) {
    double c = 0;
    for (std::size_t i = 0; i < theta.size(); ++i) {
      double d = sun::ftp(theta[i], s, std::exp(lk)) - g[i];
      c += d * d;
    }
    return c;
  };
  double lo = std::log(0.01), hi = std::log(100.0);
  const double r = (std::sqrt(5.0) - 1) / 2;
  double x1 = hi - r * (hi - lo), x2 = lo + r * (hi - lo), f1 = cost(x1), f2 = cost(x2);
  for (int it = 0; it < 100; ++it) {
    if (f1 < f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - r * (hi - lo);
      f1 = cost(x1);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + r * (hi - lo);
      f2 = cost(x2);
    }
  }
  return std::exp(0.5 * (lo + hi));
}

struct MaxDiff {
  double value = 0, theta = 0;
  void take(double d, double t) {
    if (std::abs(d) > std::abs(value)) {
      value = d;
      theta = t;
    }
  }
  nlohmann::json json() const {
    return {{"max_abs_diff", std::abs(value)}, {"signed", value}, {"at_theta_deg", deg(theta)}};
  }
};

// ---------------------------------------------------------------------------------------------

// Plot names are checked before any work or output, so a typo costs nothing.
void check_plot_name(const std::string& path) {
  if (path.empty()) return;
  auto dot = path.find_last_of('.');
  std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext != "png" && ext != "svg") throw InputError(path + ": plots are written as .png or .svg");
}

void run_ftp(const SunArgs& a) {
  check_plot_name(a.plot);
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
  if (!a.output.empty()) emit_csv(a.output, csv.str());
  if (!a.plot.empty()) p.write(a.plot);
  if (a.json) {
    print_json({{"command", "sun ftp"}, {"equation", "Sun 2002 eq. 3.4.23"}, {"curves", curves}});
  } else if (a.output.empty()) {
    emit_csv("-", csv.str());
  }
}

// ---------------------------------------------------------------------------------------------

void run_simulate(const SunArgs& a) {
  check_plot_name(a.plot);
  check_plot_name(a.plot_grid);
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

    MaxDiff sun_leave, g1_leave, h0_leave, sun_any;
    std::vector<double> th_fit, g_leave, g_any;
    PlotSeries analytic, smith, sim_l, sim_a, smith0;
    const PlotColor c = plot_palette(si);
    analytic.color = smith.color = sim_l.color = sim_a.color = smith0.color = c;
    smith.style = PlotStyle::Dashed;
    smith0.style = PlotStyle::Dotted;
    sim_l.style = sim_a.style = PlotStyle::Markers;
    sim_l.marker_size = sim_a.marker_size = 2.2;
    sim_a.marker = MarkerShape::Triangle;
    std::size_t rays = 0;
    for (const auto& pt : r.points) {
      const double t = pt.theta;
      const double g = sun::ftp(t, s), g1 = sun::smith_g1(t, s),
                   g0 = sun::smith_at_mean_plane(t, s);
      const bool simulated = t < M_PI / 2 - 1e-12;
      csv << num(s) << ',' << num(t / kDeg) << ',' << num(pt.gamma_leaving) << ','
          << num(pt.se_leaving) << ',' << num(pt.gamma_any) << ',' << num(pt.se_any) << ','
          << pt.rays << ',' << pt.rays_leaving << ',' << pt.free << ',' << num(g) << ',' << num(g1)
          << ',' << num(g0) << '\n';
      rays += pt.rays;
      analytic.x.push_back(t / kDeg);
      analytic.y.push_back(g);
      smith.x.push_back(t / kDeg);
      smith.y.push_back(g1);
      smith0.x.push_back(t / kDeg);
      smith0.y.push_back(g0);
      if (!simulated) continue;
      sun_leave.take(pt.gamma_leaving - g, t);
      g1_leave.take(pt.gamma_leaving - g1, t);
      h0_leave.take(pt.gamma_leaving - g0, t);
      sun_any.take(pt.gamma_any - g, t);
      th_fit.push_back(t);
      g_leave.push_back(pt.gamma_leaving);
      g_any.push_back(pt.gamma_any);
      sim_l.x.push_back(t / kDeg);
      sim_l.y.push_back(pt.gamma_leaving);
      sim_l.y_err.push_back(pt.se_leaving);
      sim_a.x.push_back(t / kDeg);
      sim_a.y.push_back(pt.gamma_any);
      sim_a.y_err.push_back(pt.se_any);
    }
    total_rays += static_cast<double>(rays);
    double max_se = 0;
    for (const auto& pt : r.points) max_se = std::max(max_se, pt.se_leaving);
    const double k_leave = th_fit.empty() ? NAN : fit_k_tau(s, th_fit, g_leave);
    const double k_any = th_fit.empty() ? NAN : fit_k_tau(s, th_fit, g_any);
    per_s.push_back({{"s", s},
                     {"profiles", r.profiles},
                     {"crossings", r.crossings},
                     {"excluded_crossings", r.excluded},
                     {"slope_rms", r.slope_rms},
                     {"slope_rms_expected", std::sqrt(2.0) / s},
                     {"max_standard_error_leaving", max_se},
                     {"leaving_minus_sun", sun_leave.json()},
                     {"leaving_minus_smith_g1", g1_leave.json()},
                     {"leaving_minus_smith_mean_plane", h0_leave.json()},
                     {"any_minus_sun", sun_any.json()},
                     {"best_k_tau_leaving", k_leave},
                     {"best_k_tau_any", k_any},
                     {"seconds", sec},
                     {"rays", rays}});
    if (!a.json)
      std::fprintf(stderr,
                   "microbrdf sun: s = %g: %zu crossings on %zu profiles; max |sim - Sun| = %.3f "
                   "at %.0f deg "
                   "(rays leaving above), %.3f at %.0f deg (any crossing); max |sim - Smith G1| = "
                   "%.3f at %.0f deg; "
                   "max |sim - Smith(h=0)| = %.3f at %.0f deg; max s.e. %.4f; best k tau %.3g / "
                   "%.3g; %.1f s\n",
                   s, r.crossings, r.profiles, std::abs(sun_leave.value), sun_leave.theta / kDeg,
                   std::abs(sun_any.value), sun_any.theta / kDeg, std::abs(g1_leave.value),
                   g1_leave.theta / kDeg, std::abs(h0_leave.value), h0_leave.theta / kDeg, max_se,
                   k_leave, k_any, sec);

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

  if (!a.output.empty()) emit_csv(a.output, csv.str());
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

// ---------------------------------------------------------------------------------------------

void run_slice(const SunArgs& a) {
  check_plot_name(a.plot);
  if (a.s.size() != 1) throw InputError("slice: give one --s value");
  const double s = a.s[0];
  check_s_list(a.s);
  const double ti = parse_angle(a.theta_i);
  if (!(ti >= 0 && ti < M_PI / 2)) throw InputError("--theta-i must be in [0, 90) deg");
  const bool have_nk = !std::isnan(a.n) || !std::isnan(a.k);
  if (have_nk && (std::isnan(a.n) || std::isnan(a.k) || !(a.n > 0) || a.k < 0))
    throw InputError("--n and --k go together (n > 0, k >= 0)");
  // The shared exact conductor Fresnel (complex index n + ik, constant in wavelength).
  std::shared_ptr<const Fresnel> fresnel;
  if (have_nk) fresnel = std::make_shared<ConductorFresnel>(constant_index(a.n, a.k));
  const Fresnel* F = fresnel.get();
  constexpr double kLambda = 555e-9;  // irrelevant for a constant index
  const double step = parse_angle(a.theta_step);
  if (!(step > 0) || step > M_PI / 4) throw InputError("--theta-step must be in (0, 45] deg");

  // Light at azimuth 0; theta_o > 0 on the far side (mirror direction at theta_o = theta_i).
  const Eigen::Vector3d wi(std::sin(ti), 0, std::cos(ti));
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
    const Eigen::Vector3d wo(-std::sin(to), 0, std::cos(to));
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
  std::snprintf(title, sizeof title, "Sun 2002 BRDF, plane of incidence: s = %g, θi = %g°%s", s,
                ti / kDeg, have_nk ? "" : ", R = 1");
  p.title = title;
  if (have_nk) p.title += ", n = " + num(a.n) + " + " + num(a.k) + "i";
  p.x.label = "viewing angle θo (deg; > 0 on the mirror side)";
  p.y.label = "BRDF (1/sr)";
  if (a.log_y) p.y.scale = AxisScale::Log;
  p.add(pub);
  p.add(stdf);
  if (!a.output.empty()) emit_csv(a.output, csv.str());
  if (!a.plot.empty()) p.write(a.plot);
  if (a.json) {
    print_json(
        {{"command", "sun slice"},
         {"s", s},
         {"theta_i_deg", deg(ti)},
         {"fresnel", have_nk ? nlohmann::json{{"n", a.n}, {"k", a.k}} : nlohmann::json("R = 1")},
         {"albedo_as_published", sun::albedo(ti, s, sun::BrdfForm::AsPublished, F, kLambda)},
         {"albedo_standard", sun::albedo(ti, s, sun::BrdfForm::Standard, F, kLambda)},
         {"peak_as_published", {{"value", peak_pub}, {"theta_o_deg", deg(at_pub)}}},
         {"peak_standard", {{"value", peak_std}, {"theta_o_deg", deg(at_std)}}}});
  } else if (a.output.empty()) {
    emit_csv("-", csv.str());
  }
}

void add_s(CLI::App* c, SunArgs& a, bool list) {
  auto* o =
      c->add_option("--s", a.s,
                    list ? "Smoothness tau/sigma, one value or a list: 0.5 or 0.1,0.25,0.5,1,2,5"
                         : "Smoothness tau/sigma (correlation length / rms height)");
  o->required();
  if (list) o->delimiter(',');
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
      "  microbrdf sun slice --s 2 --theta-i 30deg --n 0.2 --k 3.0 -o slice.csv --plot slice.png");

  auto* f = sunc->add_subcommand(
      "ftp", "Gamma_0(theta; s) of eq. 3.4.23 with Smith's G1 for the same surface");
  add_s(f, *a, true);
  f->add_option("--theta-step", a->theta_step, "Angle step")->capture_default_str();
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
      ->capture_default_str();
  m->add_option("--seed", a->seed, "Random seed (same seed, same result)")->capture_default_str();
  m->add_option("--theta-step", a->theta_step, "Angle step (90 deg is exactly 0, not simulated)")
      ->capture_default_str();
  m->add_option("--theta-max", a->theta_max, "Largest angle")->capture_default_str();
  m->add_option("--samples-per-tau", a->samples_per_tau, "Profile samples per correlation length")
      ->capture_default_str();
  m->add_option("--profile-length", a->profile_length, "Samples per profile holding crossings")
      ->capture_default_str();
  m->add_option("-o,--output", a->output, "CSV file of every (s, theta) point");
  m->add_option("--plot", a->plot, "Figure like Sun's Fig. 7, all s in one panel (.png or .svg)");
  m->add_option("--plot-grid", a->plot_grid, "One panel per s, with Smith at h = 0 and error bars");
  m->add_flag("--json", a->json, "Print the agreement summary as JSON on stdout");
  m->callback([a] { run_guarded("sun", [&] { run_simulate(*a); }); });

  auto* sl = sunc->add_subcommand(
      "slice", "The analytic BRDF (eq. 3.5.3) in the plane of incidence, both forms");
  add_s(sl, *a, false);
  sl->add_option("--theta-i", a->theta_i, "Polar angle of the light")->capture_default_str();
  sl->add_option("--theta-step", a->theta_step, "Viewing angle step")->capture_default_str();
  sl->add_option("--n", a->n,
                 "Real part of the metal's relative refractive index (with --k; default R = 1)");
  sl->add_option("--k", a->k, "Extinction coefficient (imaginary part)");
  sl->add_flag("--log", a->log_y, "Logarithmic BRDF axis in the plot");
  sl->add_option("-o,--output", a->output, "CSV file (default: CSV on stdout)");
  sl->add_option("--plot", a->plot, "Also draw the slice (.png or .svg)");
  sl->add_flag("--json", a->json, "Print a summary (peaks, albedos) as JSON on stdout");
  sl->callback([a] { run_guarded("sun", [&] { run_slice(*a); }); });
}

}  // namespace microbrdf::cli
