// The scattering regime (include/microbrdf/regime.hpp): the Rayleigh parameter by its own
// formula, each regime and the thresholds between them.
#include <gtest/gtest.h>

#include <cmath>

#include "microbrdf/error.hpp"
#include "microbrdf/regime.hpp"

using namespace microbrdf;

namespace {
RegimeInput surface(double sigma, double slope, double tau, double theta_deg = 0) {
  RegimeInput in;
  in.sigma_m = sigma;
  in.slope_rms = slope;
  in.corr_length_m = tau;
  in.wavelength_m = 555e-9;
  in.theta_i = theta_deg * M_PI / 180;
  return in;
}
}  // namespace

TEST(regime, PolishedMetalIsRayleighRice) {
  const RegimeVerdict v = scattering_regime(surface(5e-9, 0.002, 5e-6));
  EXPECT_EQ(v.method, "rayleigh-rice");
  const double g = std::pow(4 * M_PI * 5e-9 / 555e-9, 2);  // 0.0128
  EXPECT_NEAR(v.rayleigh_parameter, g, 1e-15);
  EXPECT_NEAR(v.specular_share, std::exp(-g), 1e-15);
  EXPECT_NE(v.reason.find("0.0128"), std::string::npos) << v.reason;
  EXPECT_TRUE(regime_allows(v, "kirchhoff"));
  EXPECT_FALSE(regime_allows(v, "geometric"));
}

TEST(regime, GrazingIncidenceMakesARougherSurfaceSmooth) {
  // sigma 30 nm: g = 0.46 at normal incidence (Kirchhoff), 0.054 at 70 deg (cos^2 = 0.117).
  EXPECT_EQ(scattering_regime(surface(30e-9, 0.01, 5e-6, 0)).method, "kirchhoff");
  const RegimeVerdict v = scattering_regime(surface(30e-9, 0.01, 5e-6, 70));
  EXPECT_EQ(v.method, "rayleigh-rice");
  EXPECT_NEAR(v.rayleigh_parameter,
              std::pow(4 * M_PI * 30e-9 * std::cos(70 * M_PI / 180) / 555e-9, 2), 1e-15);
}

TEST(regime, SteepOrIntermediateSurfacesAreKirchhoff) {
  EXPECT_EQ(scattering_regime(surface(5e-9, 0.2, 5e-6)).method, "kirchhoff");     // smooth, steep
  EXPECT_EQ(scattering_regime(surface(100e-9, 0.05, 5e-6)).method, "kirchhoff");  // g = 5.1
}

TEST(regime, RoughWideFeaturesAreGeometric) {
  const RegimeVerdict v = scattering_regime(surface(0.3e-6, 0.2, 5e-6));  // g = 46
  EXPECT_EQ(v.method, "geometric");
  EXPECT_NEAR(v.tau_over_lambda, 5e-6 / 555e-9, 1e-12);
  EXPECT_TRUE(regime_allows(v, "kirchhoff"));
  EXPECT_FALSE(regime_allows(v, "rayleigh-rice"));
}

TEST(regime, FeaturesBelowTheWavelengthLeaveNoValidMethod) {
  const RegimeVerdict v = scattering_regime(surface(0.3e-6, 0.8, 0.3e-6));
  EXPECT_EQ(v.method, "kirchhoff");
  EXPECT_TRUE(v.none_strictly_valid);
  EXPECT_NE(v.reason.find("tangent planes fail"), std::string::npos) << v.reason;
}

TEST(regime, BadNumbersAreRefused) {
  EXPECT_THROW(scattering_regime(surface(-1e-9, 0.1, 1e-6)), InputError);
  RegimeInput in = surface(1e-9, 0.1, 1e-6);
  in.wavelength_m = 0;
  EXPECT_THROW(scattering_regime(in), InputError);
}
