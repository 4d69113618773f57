// Scattering regime of a surface (include/microbrdf/regime.hpp, docs/regime.md).
#include "microbrdf/regime.hpp"

#include <cmath>
#include <cstdio>

#include "microbrdf/error.hpp"

namespace microbrdf {

RegimeVerdict scattering_regime(const RegimeInput& in) {
  if (!(in.wavelength_m > 0)) throw InputError("regime: the wavelength must be > 0");
  if (!(in.sigma_m >= 0) || !(in.slope_rms >= 0))
    throw InputError("regime: rms height and slope must be >= 0");
  RegimeVerdict v;
  const double k = 4 * M_PI * in.sigma_m * std::cos(in.theta_i) / in.wavelength_m;
  v.rayleigh_parameter = k * k;
  v.specular_share = std::exp(-v.rayleigh_parameter);
  const bool tau_known = std::isfinite(in.corr_length_m) && in.corr_length_m > 0;
  v.tau_over_lambda = tau_known ? in.corr_length_m / in.wavelength_m : NAN;
  const bool narrow = tau_known && v.tau_over_lambda < kRegimeMinTauOverLambda;
  const double g = v.rayleigh_parameter;
  char buf[400];
  if (g < kRegimeSmoothG && in.slope_rms < kRegimeSmoothSlope) {
    v.method = "rayleigh-rice";
    std::snprintf(buf, sizeof buf,
                  "Rayleigh parameter (4 pi sigma cos theta / lambda)^2 = %.3g < %.3g and rms "
                  "slope %.3g < %.3g: smooth, first-order perturbation holds (specular share "
                  "%.3g)",
                  g, kRegimeSmoothG, in.slope_rms, kRegimeSmoothSlope, v.specular_share);
  } else if (g > kRegimeGeometricG && !narrow) {
    v.method = "geometric";
    std::snprintf(buf, sizeof buf,
                  "Rayleigh parameter %.3g > %.3g (no specular part left) and correlation length "
                  "%.3g wavelengths: rough, geometric optics holds",
                  g, kRegimeGeometricG, v.tau_over_lambda);
  } else {
    v.method = "kirchhoff";
    v.none_strictly_valid = narrow;
    if (narrow)
      std::snprintf(buf, sizeof buf,
                    "Rayleigh parameter %.3g with rms slope %.3g, but the correlation length is "
                    "only %.3g wavelengths: tangent planes fail and first order does not hold; "
                    "Kirchhoff is the nearest",
                    g, in.slope_rms, v.tau_over_lambda);
    else if (g < kRegimeSmoothG)
      std::snprintf(buf, sizeof buf,
                    "Rayleigh parameter %.3g < %.3g but rms slope %.3g >= %.3g: smooth but steep, "
                    "the Kirchhoff integral holds",
                    g, kRegimeSmoothG, in.slope_rms, kRegimeSmoothSlope);
    else
      std::snprintf(buf, sizeof buf,
                    "Rayleigh parameter %.3g between %.3g and %.3g: neither smooth nor rough, the "
                    "Kirchhoff integral holds",
                    g, kRegimeSmoothG, kRegimeGeometricG);
  }
  v.reason = buf;
  return v;
}

bool regime_allows(const RegimeVerdict& v, const std::string& method) {
  if (method == v.method) return true;
  if (method == "kirchhoff") return v.method == "geometric" || v.method == "rayleigh-rice";
  return false;
}

}  // namespace microbrdf
