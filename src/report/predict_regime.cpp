// predict: the scattering regime of the scans at the slices' wavelength and incidences
// (include/microbrdf/regime.hpp, docs/regime.md). stage_theory (predict_theory.cpp) picks the
// theory of the run's BRDF from it.
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
  c.log("regime: " + per.front().at("method").get<std::string>() + " at normal incidence (" +
        per.front().at("reason").get<std::string>() + ")");
  return out;
}

}  // namespace microbrdf::report
