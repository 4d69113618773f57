// Sampled spectra, CIE tables and sRGB (include/microbrdf/spectrum.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "microbrdf/error.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/spectrum.hpp"

using namespace microbrdf;

TEST(spectrum, LinearInterpolationAndClamping) {
  auto s = Spectrum::from_nm({400, 500, 700}, {1, 3, 2});
  EXPECT_NEAR(s(450e-9), 2.0, 1e-14);
  EXPECT_NEAR(s.at_nm(600), 2.5, 1e-14);
  EXPECT_DOUBLE_EQ(s(300e-9), 1.0);
  EXPECT_DOUBLE_EQ(s(900e-9), 2.0);
  EXPECT_DOUBLE_EQ(s.at_nm(500), 3.0);
  EXPECT_THROW(Spectrum::from_nm({400, 400}, {1, 2}), InputError);
  EXPECT_THROW(Spectrum::from_nm({400}, {1, 2}), InputError);
  EXPECT_DOUBLE_EQ(Spectrum::constant(0.7)(1e-6), 0.7);
}

TEST(spectrum, CieTablesFromColord) {
  // Values quoted in data/color/README.md.
  EXPECT_NEAR(cie1931_x().at_nm(555), 0.5120501, 1e-12);
  EXPECT_NEAR(cie1931_y().at_nm(555), 1.0, 1e-12);
  EXPECT_NEAR(cie_d65().at_nm(300), 0.000341, 1e-12);
  EXPECT_NEAR(cie_d65().at_nm(560), 1.0, 1e-12);
  EXPECT_EQ(cie1931_x().size(), 95u);
  EXPECT_EQ(cie_d65().size(), 107u);
  EXPECT_EQ(colour_wavelengths().size(), 95u);
  EXPECT_NEAR(colour_wavelengths().front(), 360e-9, 1e-20);
}

TEST(spectrum, PerfectWhiteIsD65White) {
  auto xyz = reflectance_to_xyz(Spectrum::constant(1.0));
  EXPECT_NEAR(xyz[1], 1.0, 1e-14);
  double sum = xyz.sum();
  EXPECT_NEAR(xyz[0] / sum, 0.3127, 2e-4);  // D65 chromaticity (CIE 15)
  EXPECT_NEAR(xyz[1] / sum, 0.3290, 2e-4);
  auto rgb = xyz_to_linear_srgb(xyz);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(rgb[i], 1.0, 3e-3) << i;
  auto c8 = linear_srgb_to_srgb8(rgb);
  EXPECT_EQ(srgb8_hex(c8), "#ffffff");
  // A 18% grey.
  auto g = xyz_to_linear_srgb(reflectance_to_xyz(Spectrum::constant(0.18)));
  EXPECT_NEAR(g[1], 0.18, 1e-3);
}

TEST(spectrum, SrgbMatrixAndTransfer) {
  auto m = xyz_to_linear_srgb_matrix();
  // IEC 61966-2-1 gives this matrix rounded to 4 digits (its rounding is off by up to 4e-4 from
  // the exact inverse of the primaries matrix).
  EXPECT_NEAR(m(0, 0), 3.2406, 5e-4);
  EXPECT_NEAR(m(0, 1), -1.5372, 5e-4);
  EXPECT_NEAR(m(1, 0), -0.9689, 5e-4);
  EXPECT_NEAR(m(2, 2), 1.0570, 5e-4);
  for (double v : {0.0, 0.001, 0.2, 0.5, 1.0}) EXPECT_NEAR(srgb_decode(srgb_encode(v)), v, 1e-12);
  EXPECT_NEAR(srgb_encode(0.5), 0.7353569830524495, 1e-12);
  // Clipped to [0, 1] (what an 8-bit PNG shows; the report's SSIM compares these values), and
  // the linear toe 12.92 x below 0.0031308.
  EXPECT_EQ(srgb_encode(-1), 0.0);
  EXPECT_EQ(srgb_encode(2), 1.0);
  EXPECT_NEAR(srgb_encode(0.002), 0.02584, 1e-12);
}

TEST(spectrum, SmoothSpectrumRoundTrip) {
  for (auto c : {Eigen::Vector3d(0.5, 0.5, 0.5), Eigen::Vector3d(0.9, 0.6, 0.15),
                 Eigen::Vector3d(0.2, 0.4, 0.7), Eigen::Vector3d(0.95, 0.93, 0.88)}) {
    auto s = smooth_reflectance_from_linear_srgb(c);
    auto back = xyz_to_linear_srgb(reflectance_to_xyz(s));
    EXPECT_NEAR((back - c).norm(), 0, 1e-6);
    for (double v : s.values()) {
      EXPECT_GT(v, 0);
      EXPECT_LT(v, 1);
    }
  }
  EXPECT_THROW(smooth_reflectance_from_linear_srgb(Eigen::Vector3d(1.2, 0.5, 0.5)), InputError);
}

TEST(spectrum, MetalColours) {
  // Documented in docs/models.md: normal-incidence sRGB of the built-in metals under D65.
  struct Expect {
    const char* name;
    const char* hex;
  };
  for (const auto& name : metal_names()) {
    auto rgb = xyz_to_linear_srgb(reflectance_to_xyz(metal(name).normal_reflectance_spectrum()));
    auto c8 = linear_srgb_to_srgb8(rgb);
    std::printf("%-14s linear sRGB %.4f %.4f %.4f   sRGB8 %3d %3d %3d  %s\n", name.c_str(), rgb[0],
                rgb[1], rgb[2], c8[0], c8[1], c8[2], srgb8_hex(c8).c_str());
  }
  auto col = [](const char* m) {
    return xyz_to_linear_srgb(reflectance_to_xyz(metal(m).normal_reflectance_spectrum()));
  };
  auto au = col("Au"), cu = col("Cu"), ag = col("Ag"), al = col("Al");
  // Gold: yellow (R > G >> B); copper: orange-red (R > G > B, R/G larger than gold's? no: lower G).
  EXPECT_GT(au[0], au[1]);
  EXPECT_GT(au[1], 1.5 * au[2]);
  EXPECT_GT(cu[0], 1.3 * cu[1]);
  EXPECT_GT(cu[1], cu[2]);
  EXPECT_GT(cu[0] / cu[1], au[0] / au[1]);  // copper redder than gold
  // Silver and aluminium: near-neutral and bright.
  for (const auto& v : {ag, al}) {
    EXPECT_LT(v.maxCoeff() / v.minCoeff(), 1.12);
    EXPECT_GT(v.minCoeff(), 0.8);
  }
}
