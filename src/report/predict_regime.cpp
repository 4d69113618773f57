// predict: the scattering regime of the scans at the slices' wavelength and incidences
// (include/microbrdf/regime.hpp, docs/regime.md). stage_theory (predict_theory.cpp) picks the
// theory of the run's BRDF from it.
#include "report/predict_regime.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>

#include "microbrdf/plot.hpp"
#include "microbrdf/regime.hpp"
#include "report/html.hpp"
#include "report/predict_stages.hpp"

namespace microbrdf::report {

namespace {
double number(const nlohmann::json& j, const char* key) {
  return j.contains(key) && j[key].is_number() ? j[key].get<double>() : NAN;
}

// The map: Rayleigh parameter g against rms slope (both log), the three regions bounded by the
// thresholds of regime.hpp, and the scans as one point per incidence (g falls as cos^2 theta).
// Each boundary is where two methods part by a stated amount (docs/regime.md "Thresholds"):
// at g = 0.1 first-order Rayleigh-Rice lies within ~5 % of the Kirchhoff series (its second
// order is g/2 of the first), at g = 10 the specular share exp(-g) of Kirchhoff drops below
// 5e-5 and its lobe has become the slope distribution's.
void write_regime_map(const std::string& path, const nlohmann::json& per, double slope) {
  constexpr double gx0 = 1e-4, sy0 = 1e-4, sy1 = 3;
  double gx1 = 1e4;  // wide enough for the roughest scan's points
  for (const auto& q : per) gx1 = std::max(gx1, 3 * q.at("rayleigh_parameter").get<double>());
  Plot p;
  p.title = "Scattering regime of the scans";
  p.x.label = "Rayleigh parameter g = (4 pi sigma cos theta_i / lambda)^2";
  p.y.label = "rms slope (per axis)";
  p.x.scale = p.y.scale = AxisScale::Log;
  p.x.min = gx0;
  p.x.max = gx1;
  p.y.min = sy0;
  p.y.max = sy1;
  auto band = [&](double x0, double x1, double y0, double y1, const char* label, PlotColor col) {
    PlotSeries b({x0, x1}, {y0, y1}, label);
    b.band_lo = {y0, y0};
    b.band_hi = {y1, y1};
    b.y = {y1, y1};
    b.color = col;
    b.line_width = 0.5;
    p.add(b);
  };
  band(gx0, kRegimeSmoothG, sy0, kRegimeSmoothSlope, "Rayleigh-Rice (and Kirchhoff)",
       {0.55, 0.75, 0.95});
  band(kRegimeGeometricG, gx1, sy0, sy1, "geometric (and Kirchhoff)", {0.95, 0.7, 0.45});
  PlotSeries l1({kRegimeSmoothG, kRegimeSmoothG}, {sy0, kRegimeSmoothSlope},
                "g = 0.1: first order within ~5 % of the series", PlotStyle::Dashed);
  l1.color = PlotColor{0.2, 0.3, 0.7};
  p.add(l1);
  PlotSeries l2({kRegimeGeometricG, kRegimeGeometricG}, {sy0, sy1},
                "g = 10: specular share exp(-g) < 5e-5", PlotStyle::Dashed);
  l2.color = PlotColor{0.7, 0.35, 0.1};
  p.add(l2);
  std::vector<double> gs, ss;
  for (const auto& q : per) {
    gs.push_back(std::max(q.at("rayleigh_parameter").get<double>(), gx0));
    ss.push_back(std::clamp(slope, sy0, sy1));
  }
  PlotSeries pts(gs, ss, "the scans at theta_i 0 and the slices' angles (white: Kirchhoff only)",
                 PlotStyle::LineMarkers);
  pts.color = PlotColor{0, 0, 0};
  pts.marker_size = 4.5;
  p.add(pts);
  p.legend = LegendPlace::TopLeft;
  p.write_svg(path, 640, 420);
}
}  // namespace

nlohmann::json stage_regime(const Context& c, const nlohmann::json& inputs) {
  // The scans together: the mean of their rms height, rms slope (per axis) and correlation
  // length (scans that cannot show theirs are left out of that mean).
  double sq = 0, slope = 0, tau = 0;
  std::size_t n = 0, ntau = 0;
  for (const auto& rec : inputs) {
    const auto& st = rec.at("stats");
    const double s = number(st, "sq_m"), sx = number(st, "slope_rms_x"),
                 sy = number(st, "slope_rms_y"), t = number(st, "corr_length_m");
    if (!std::isfinite(s) || !std::isfinite(sx) || !std::isfinite(sy)) continue;
    sq += s;
    slope += std::sqrt(0.5 * (sx * sx + sy * sy));
    ++n;
    if (std::isfinite(t) && t > 0) {
      tau += t;
      ++ntau;
    }
  }
  if (n == 0) return nullptr;
  RegimeInput in;
  in.sigma_m = sq / static_cast<double>(n);
  in.slope_rms = slope / static_cast<double>(n);
  in.corr_length_m = ntau ? tau / static_cast<double>(ntau) : NAN;
  in.wavelength_m = c.opt.wavelength_m;
  nlohmann::json per = nlohmann::json::array();
  std::set<std::string> methods;
  std::vector<double> angles{0.0};
  angles.insert(angles.end(), c.opt.slice_theta_i_rad.begin(), c.opt.slice_theta_i_rad.end());
  for (double ti : angles) {
    in.theta_i = ti;
    const RegimeVerdict v = scattering_regime(in);
    methods.insert(v.method);
    per.push_back({{"theta_i_deg", ti * 180 / M_PI},
                   {"method", v.method},
                   {"rayleigh_parameter", v.rayleigh_parameter},
                   {"specular_share", v.specular_share},
                   {"tau_over_lambda", ntau ? nlohmann::json(v.tau_over_lambda) : nullptr},
                   {"none_strictly_valid", v.none_strictly_valid},
                   {"reason", v.reason}});
  }
  nlohmann::json out = {{"wavelength_m", in.wavelength_m},
                        {"sigma_m", in.sigma_m},
                        {"slope_rms", in.slope_rms},
                        {"corr_length_m", ntau ? nlohmann::json(in.corr_length_m) : nullptr},
                        {"scans", n},
                        {"methods", methods},
                        {"per_incidence", per}};
  write_regime_map(c.path("img/regime_map.svg"), per, in.slope_rms);
  out["map"] = "img/regime_map.svg";
  c.log("regime: " + per.front().at("method").get<std::string>() + " at normal incidence (" +
        per.front().at("reason").get<std::string>() + ")");
  return out;
}

std::string regime_section_html(const nlohmann::json& s, const std::string& dir) {
  if (!s.contains("regime") || !s["regime"].is_object()) return "";
  const auto& r = s["regime"];
  std::ostringstream p;
  p << "<h3 id=\"regime\">Scattering regime and the theory of the predicted BRDF</h3>\n";
  if (r.contains("theory") && r["theory"].is_object()) {
    const auto& t = r["theory"];
    p << "<p>The predicted BRDF (slices, renders) uses <b>" << escape(t.value("chosen", ""))
      << "</b> scattering: " << escape(t.value("why", "")) << ".</p>\n";
  }
  p << "<p>Mean over " << r.value("scans", 0) << " scan(s): Sq " << length(number(r, "sigma_m"))
    << ", rms slope " << num(number(r, "slope_rms")) << ", correlation length "
    << (r["corr_length_m"].is_number() ? length(r["corr_length_m"].get<double>()) : "—")
    << ", wavelength " << length(number(r, "wavelength_m"))
    << ".</p>\n<table>\n<tr><th>theta_i</th><th>Rayleigh parameter g</th><th>specular share "
       "exp(−g)</th><th>valid theory</th><th>the run's theory valid</th></tr>\n";
  for (const auto& q : r["per_incidence"])
    p << "<tr><td class=\"n\">" << num(number(q, "theta_i_deg")) << " deg</td><td class=\"n\">"
      << num(number(q, "rayleigh_parameter")) << "</td><td class=\"n\">"
      << num(number(q, "specular_share")) << "</td><td>" << escape(q.value("method", ""))
      << (q.value("none_strictly_valid", false) ? " (none strictly: tau &lt; lambda)" : "")
      << "</td><td>"
      << (q.contains("used_is_valid") ? (q["used_is_valid"].get<bool>() ? "yes" : "<b>no</b>")
                                      : "—")
      << "</td></tr>\n";
  p << "</table>\n";
  if (r.contains("map") && r["map"].is_string())
    p << "<figure>"
      << inline_svg((std::filesystem::path(dir) / r["map"].get<std::string>()).string(), "regime-")
      << "<figcaption>The scans on the regime map, one point per incidence (docs/regime.md). "
         "Kirchhoff holds in all three regions while the correlation length exceeds the "
         "wavelength; Rayleigh-Rice only in the smooth one, geometric optics only in the rough "
         "one.</figcaption></figure>\n";
  return p.str();
}

}  // namespace microbrdf::report
