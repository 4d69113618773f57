// Fresnel reflectance and optical constants (docs/theory.md §5.3-5.5, 9.8).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "microbrdf/error.hpp"
#include "microbrdf/fresnel.hpp"

using namespace microbrdf;

namespace {
double deg(double d) { return d * M_PI / 180; }
}  // namespace

TEST(fresnel, ConductorNormalIncidenceMatchesClosedForm) {
  for (auto [n, k] : {std::pair{2.76, 3.79}, {1.0, 2.0}, {0.05, 3.6}, {2.95, 2.93}, {1.5, 0.0}}) {
    double r0 = ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
    EXPECT_NEAR(fresnel_conductor(1.0, {n, k}), r0, 1e-14) << n << " " << k;
    EXPECT_NEAR(fresnel_conductor_siegel(1.0, n, k), r0, 1e-14);
    EXPECT_NEAR(normal_reflectance(n, k), r0, 1e-15);
  }
}

TEST(fresnel, ConductorGrazingIsOne) {
  for (auto [n, k] : {std::pair{2.76, 3.79}, {1.0, 2.0}, {0.05, 3.6}, {0.2, 0.1}}) {
    EXPECT_NEAR(fresnel_conductor(0.0, {n, k}), 1.0, 1e-14);
    EXPECT_NEAR(fresnel_conductor_siegel(0.0, n, k), 1.0, 1e-14);
    EXPECT_GT(fresnel_conductor(1e-4, {n, k}), 0.99);
  }
}

TEST(fresnel, ConductorReferenceValuesTheory54) {
  const double th[] = {0, 30, 45, 60, 75, 85};
  const double a[] = {0.6127, 0.6113, 0.6055, 0.5887, 0.5683, 0.6826};  // eta 2.76, kappa 3.79
  const double b[] = {0.5000, 0.5010, 0.5065, 0.5294, 0.6244, 0.8198};  // eta 1, kappa 2
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(fresnel_conductor(std::cos(deg(th[i])), {2.76, 3.79}), a[i], 6e-5) << th[i];
    EXPECT_NEAR(fresnel_conductor(std::cos(deg(th[i])), {1.0, 2.0}), b[i], 6e-5) << th[i];
  }
  EXPECT_NEAR(fresnel_conductor(1, {2.95, 2.93}), 0.5121, 6e-5);
  EXPECT_NEAR(fresnel_conductor(std::cos(deg(45)), {2.95, 2.93}), 0.5073, 6e-5);
  EXPECT_NEAR(fresnel_conductor(std::cos(deg(75)), {2.95, 2.93}), 0.5005, 6e-5);
}

TEST(fresnel, ComplexAndSiegelFormsAgree) {
  double worst = 0;
  for (double n : {0.03, 0.2, 0.5, 1.0, 1.7, 2.9, 4.0})
    for (double k : {0.0, 0.01, 0.5, 2.0, 3.8, 7.0})
      for (int i = 0; i <= 90; ++i) {
        double c = std::cos(deg(i));
        worst = std::max(
            worst, std::abs(fresnel_conductor(c, {n, k}) - fresnel_conductor_siegel(c, n, k)));
      }
  EXPECT_LT(worst, 1e-12);
}

TEST(fresnel, SunAsPrintedDiffersFromExact) {
  // docs/theory.md §5.3: eq. 5.7/5.8 as printed are wrong off normal incidence.
  double c75 = std::cos(deg(75));
  EXPECT_GT(std::abs(fresnel_conductor_sun_as_printed(c75, 1.0, 2.0) -
                     fresnel_conductor(c75, {1.0, 2.0})),
            0.02);
}

TEST(fresnel, DielectricLimitsAndTotalInternalReflection) {
  EXPECT_NEAR(fresnel_dielectric(1, 1.5), 0.04, 1e-15);
  EXPECT_NEAR(fresnel_dielectric(0, 1.5), 1.0, 1e-15);
  // Brewster angle: R_p = 0, so R = R_s / 2.
  double tb = std::atan(1.5), ct = std::cos(tb), st = std::sin(tb);
  double cos_t = std::sqrt(1 - st * st / 2.25);
  double rs = (ct - 1.5 * cos_t) / (ct + 1.5 * cos_t);
  EXPECT_NEAR(fresnel_dielectric(ct, 1.5), 0.5 * rs * rs, 1e-14);
  // From inside glass: critical angle asin(1/1.5) = 41.81 deg.
  EXPECT_EQ(fresnel_dielectric(-std::cos(deg(42)), 1.5), 1.0);
  EXPECT_LT(fresnel_dielectric(-std::cos(deg(41)), 1.5), 1.0);
  EXPECT_NEAR(fresnel_dielectric(-1, 1.5), 0.04, 1e-15);
  // The dielectric equals the conductor formula with kappa = 0.
  for (int i = 0; i <= 90; i += 5)
    EXPECT_NEAR(fresnel_dielectric(std::cos(deg(i)), 1.7),
                fresnel_conductor(std::cos(deg(i)), {1.7, 0}), 1e-14);
}

TEST(fresnel, Schlick) {
  EXPECT_DOUBLE_EQ(fresnel_schlick(1, 0.3), 0.3);
  EXPECT_DOUBLE_EQ(fresnel_schlick(0, 0.3), 1.0);
}

TEST(fresnel, KappaFromNormalReflectance) {
  for (double r0 : {0.0, 0.04, 0.5, 0.9, 0.98}) {
    double k = kappa_from_normal_reflectance(r0, 1.0);
    EXPECT_NEAR(k, 2 * std::sqrt(r0 / (1 - r0)), 1e-12);
    EXPECT_NEAR(normal_reflectance(1.0, k), r0, 1e-13);
    double k2 = kappa_from_normal_reflectance(r0 < 0.04 ? 0.3 : r0, 1.5);
    EXPECT_NEAR(normal_reflectance(1.5, k2), r0 < 0.04 ? 0.3 : r0, 1e-13);
  }
  EXPECT_THROW(kappa_from_normal_reflectance(1.0), InputError);
  EXPECT_THROW(kappa_from_normal_reflectance(0.01, 1.5), InputError);  // below the dielectric 0.04
}

TEST(fresnel, BuiltInMetals) {
  EXPECT_EQ(metal_names().size(), 12u);
  for (const auto& name : metal_names()) {
    auto m = metal(name);
    EXPECT_LE(m.n.min_wavelength(), 360.5e-9) << name;
    EXPECT_GE(m.n.max_wavelength(), 829.5e-9) << name;
    auto r = m.normal_reflectance_spectrum();
    for (double v : r.values()) {
      EXPECT_GT(v, 0.3) << name;
      EXPECT_LT(v, 1.0) << name;
    }
  }
  // data/optical/README.md quick-check table, at the tabulated point nearest 550 nm.
  EXPECT_NEAR(normal_reflectance(metal("Ag").n.at_nm(548.6), metal("Ag").k.at_nm(548.6)), 0.983,
              1.5e-3);
  EXPECT_NEAR(metal("Cu").k.at_nm(548.6), 2.577, 1e-12);  // JC Cu at 548.6 nm (table row)
  EXPECT_EQ(metal("au").name, "Au");
  EXPECT_EQ(metal("Au_JohnsonChristy1972").name, "Au");
  EXPECT_THROW(metal("unobtainium"), InputError);
  // Interpolation is linear between the rows.
  auto au = metal("Au");
  const auto& w = au.n.wavelengths();
  double mid = 0.5 * (w[5] + w[6]);
  EXPECT_NEAR(au.n(mid), 0.5 * (au.n.values()[5] + au.n.values()[6]), 1e-15);
}

TEST(fresnel, OpticalConstantsCsv) {
  std::string path = testing::TempDir() + "/nk_test.csv";
  {
    std::ofstream f(path);
    f << "# test\nwavelength_nm,n,k\n400,1.0,2.0\n700,2.0,4.0\n";
  }
  auto c = read_optical_constants_csv(path);
  EXPECT_NEAR(c.n(550e-9), 1.5, 1e-12);
  EXPECT_NEAR(c.k(550e-9), 3.0, 1e-12);
  {
    std::ofstream f(path);
    f << "wavelength_nm,n,k\n400,1.0\n";
  }
  EXPECT_THROW(read_optical_constants_csv(path), FileError);
  EXPECT_THROW(read_optical_constants_csv(path + ".missing"), FileError);
}

TEST(fresnel, FromNormalReflectanceAndSrgb) {
  auto c = from_normal_reflectance(Spectrum::from_nm({400, 700}, {0.5, 0.9}), 1.0);
  EXPECT_NEAR(c.n(500e-9), 1.0, 0);
  EXPECT_NEAR(normal_reflectance(1, c.k(400e-9)), 0.5, 1e-13);
  EXPECT_NEAR(normal_reflectance(1, c.k(700e-9)), 0.9, 1e-13);
  // A gold-like colour round-trips through the smooth spectrum and kappa(R0).
  auto g = from_srgb(0.96, 0.80, 0.41);
  auto rgb = xyz_to_linear_srgb(reflectance_to_xyz(g.normal_reflectance_spectrum()));
  EXPECT_NEAR(rgb[0], srgb_decode(0.96), 1e-6);
  EXPECT_NEAR(rgb[1], srgb_decode(0.80), 1e-6);
  EXPECT_NEAR(rgb[2], srgb_decode(0.41), 1e-6);
  EXPECT_THROW(from_srgb(1.0, 0.5, 0.5), InputError);
}
