// predict: the scattering regime of the scans at the slices' wavelength and incidences
// (include/microbrdf/regime.hpp, docs/regime.md), and a warning when the BRDF the run renders
// and slices uses a theory outside its validity.
#include <cmath>
#include <set>
#include <string>

#include "microbrdf/regime.hpp"
#include "report/predict_stages.hpp"

namespace microbrdf::report {

namespace {
double number(const nlohmann::json& j, const char* key) {
  return j.contains(key) && j[key].is_number() ? j[key].get<double>() : NAN;
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
  // What the run's slices and renders use: the geometric NDF (naive or filtered) or D_K.
  const std::string used = c.opt.render_ndf == "kirchhoff" ? "kirchhoff" : "geometric";
  nlohmann::json per = nlohmann::json::array();
  std::set<std::string> methods;
  std::string first_smooth;
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
                   {"none_strictly_valid", v.none_strictly_valid},
                   {"used_is_valid", regime_allows(v, used)},
                   {"reason", v.reason}});
    if (v.method == "rayleigh-rice" && used == "geometric" && first_smooth.empty())
      first_smooth =
          v.reason + " at theta_i " + std::to_string(std::lround(ti * 180 / M_PI)) + " deg";
  }
  nlohmann::json out = {{"wavelength_m", in.wavelength_m},
                        {"sigma_m", in.sigma_m},
                        {"slope_rms", in.slope_rms},
                        {"corr_length_m", ntau ? nlohmann::json(in.corr_length_m) : nullptr},
                        {"scans", n},
                        {"methods", methods},
                        {"used", used},
                        {"per_incidence", per}};
  c.log("regime: " + per.front().at("method").get<std::string>() + " at normal incidence (" +
        per.front().at("reason").get<std::string>() + ")");
  // The geometric NDF has no specular part: on a smooth surface it spreads the mirror
  // reflection into a lobe of the slopes' width and misses the diffuse halo's shape.
  if (!first_smooth.empty())
    c.warn("method_outside_validity",
           "the BRDF slices and renders use the geometric (" + c.opt.render_ndf +
               ") NDF, but the surface is in the smooth (Rayleigh-Rice) regime: " + first_smooth,
           "add --kirchhoff --render-ndf kirchhoff for the wave-optics BRDF (slower), or see "
           "`microbrdf brdf slice --rayleigh-rice` (docs/regime.md)");
  return out;
}

}  // namespace microbrdf::report
