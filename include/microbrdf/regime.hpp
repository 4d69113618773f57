#pragma once
// Which scattering theory holds for a surface at a wavelength and incidence (docs/regime.md):
// first-order Rayleigh-Rice (smooth), the Kirchhoff tangent-plane integral D_K, or geometric
// optics (the slope distribution), decided from the surface's rms height sigma, rms slope and
// correlation length tau against the wavelength.

#include <string>

namespace microbrdf {

/// The numbers that decide and their thresholds (docs/regime.md "Thresholds").
struct RegimeInput {
  double sigma_m = 0;        ///< rms height after levelling (Sq), m
  double slope_rms = 0;      ///< rms slope (sqrt(s_x^2 + s_y^2) / sqrt(2): per axis), >= 0
  double corr_length_m = 0;  ///< correlation length tau, m (NaN or <= 0: unknown)
  double wavelength_m = 555e-9;
  double theta_i = 0;  ///< incidence, rad
};

/// Rayleigh-Rice holds while the Rayleigh parameter g = (4 pi sigma cos theta / lambda)^2 is below
/// this (the specular share exp(-g) above 0.9, the second-order terms below g/2 = 5 % of the
/// first) and the slopes are below kRegimeSmoothSlope.
inline constexpr double kRegimeSmoothG = 0.1;
inline constexpr double kRegimeSmoothSlope = 0.1;
/// Geometric optics holds once g exceeds this (no coherent part left: exp(-g) < 5e-5).
inline constexpr double kRegimeGeometricG = 10.0;
/// Tangent planes (Kirchhoff and geometric optics) need features wider than the wavelength.
inline constexpr double kRegimeMinTauOverLambda = 1.0;

struct RegimeVerdict {
  std::string method;             ///< "rayleigh-rice" | "kirchhoff" | "geometric"
  double rayleigh_parameter = 0;  ///< g = (4 pi sigma cos theta / lambda)^2
  double specular_share = 0;      ///< exp(-g), the coherent (specular) share of the light
  double tau_over_lambda = 0;     ///< tau / lambda (NaN when tau is unknown)
  /// True when tau < kRegimeMinTauOverLambda lambda: no method here is strictly valid (the
  /// tangent plane fails and the slopes are too steep or the height too large for first order).
  bool none_strictly_valid = false;
  std::string reason;  ///< one sentence with the numbers
};

/// Throws InputError for a non-positive wavelength or negative sigma / slope.
RegimeVerdict scattering_regime(const RegimeInput& in);

/// Whether `method` ("rayleigh-rice" | "kirchhoff" | "geometric") is valid where `v` holds:
/// Kirchhoff also holds in the geometric regime (it tends to it), and in the smooth regime for
/// small slopes (it agrees with Rayleigh-Rice to first order).
bool regime_allows(const RegimeVerdict& v, const std::string& method);

}  // namespace microbrdf
