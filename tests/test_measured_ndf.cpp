// Dong eq. 9 effective NDFs from measured BRDFs: a MERL file written from a known isotropic GGX
// conductor and a 4000-point goniometer CSV from a known anisotropic GGX conductor, each
// recovered by the NDF fit; unmeasured nodes are NaN and ignored by the fit.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <random>

#include "microbrdf/brdf.hpp"
#include "microbrdf/fit.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/image.hpp"
#include "microbrdf/measured.hpp"
#include "microbrdf/measured_compare.hpp"
#include "microbrdf/measured_ndf.hpp"
#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/ndf_io.hpp"
#include "microbrdf/ndf_preview.hpp"

using namespace microbrdf;

namespace {
constexpr double kPi = 3.14159265358979323846;

FitResult fit_ggx(const TabulatedNdf& t) {
  FitOptions o;
  o.model = "ggx";
  return fit_ndf(t, o);
}

// An isotropic GGX conductor (n 1.2, k 3.5) written as a MERL file and read back.
MerlBrdf merl_of_ggx(double alpha, int invalid_from_theta_h_bin = MerlTable::kThetaH) {
  const MicrofacetBrdf g(std::make_shared<GgxDistribution>(alpha),
                         std::make_shared<ConductorFresnel>(constant_index(1.2, 3.5)));
  MerlTable t = tabulate_merl(g);
  for (int i = invalid_from_theta_h_bin; i < MerlTable::kThetaH; ++i)
    for (int j = 0; j < MerlTable::kThetaD; ++j)
      for (int k = 0; k < MerlTable::kPhiD; ++k)
        for (int c = 0; c < 3; ++c)
          t.rgb[c * MerlTable::kBins + MerlTable::index(i, j, k)] =
              std::numeric_limits<double>::quiet_NaN();
  return MerlBrdf(parse_merl(encode_merl(t), "ggx.binary"), "ggx.binary");
}

// 4000 half vectors: 50 rings (denser towards the pole) x 80 azimuths, each measured at
// theta_d = 14.14 deg with the plane of wi, wo turned by a random angle about h.
GonioData gonio_points(const Brdf& g) {
  const double half = 14.14 * kPi / 180 / 2;
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(0, 1);
  GonioData d;
  for (int ring = 1; ring <= 50; ++ring)
    for (int k = 0; k < 80; ++k) {
      const double r = 0.85 * std::pow(ring / 50.0, 1.5), a = 2 * kPi * (k + u(rng)) / 80;
      const Vec3 h(r * std::cos(a), r * std::sin(a), std::sqrt(1 - r * r));
      const Vec3 t1 = h.cross(Vec3(0, 0, 1)).norm() > 1e-9
                          ? Vec3(h.cross(Vec3(0, 0, 1)).normalized())
                          : Vec3(1, 0, 0);
      const Vec3 t2 = h.cross(t1);
      const double psi = 2 * kPi * u(rng);
      const Vec3 b = std::cos(psi) * t1 + std::sin(psi) * t2;
      const Vec3 wi = std::cos(half) * h + std::sin(half) * b,
                 wo = std::cos(half) * h - std::sin(half) * b;
      if (wi.z() <= 0 || wo.z() <= 0) continue;
      GonioPoint p;
      p.theta_i = std::acos(wi.z());
      p.phi_i = std::atan2(wi.y(), wi.x());
      p.theta_o = std::acos(wo.z());
      p.phi_o = std::atan2(wo.y(), wo.x());
      p.wavelength_m = 550e-9;
      p.brdf = g.eval(wi, wo, 550e-9);
      d.points.push_back(p);
    }
  return d;
}
}  // namespace

TEST(MeasuredNdf, MerlOfIsotropicGgxRecoversAlpha) {
  const double alpha = 0.3;
  const MerlBrdf m = merl_of_ggx(alpha);
  const ConductorFresnel f(constant_index(1.2, 3.5));
  for (bool smith : {false, true}) {
    EffectiveNdfOptions o;
    o.resolution = 257;
    o.smith = smith;
    const TabulatedNdf t = effective_ndf(m, f, o);
    EXPECT_EQ(t.meta.method, "measured");
    const FitResult r = fit_ggx(t);
    std::printf("[ MERL ggx %.2f, G %s ] fitted alpha_x %.4f alpha_y %.4f (%+.2f%%, %+.2f%%)\n",
                alpha, smith ? "smith" : "1", r.params.at("alpha_x"), r.params.at("alpha_y"),
                100 * (r.params.at("alpha_x") / alpha - 1),
                100 * (r.params.at("alpha_y") / alpha - 1));
    EXPECT_NEAR(r.params.at("alpha_x"), alpha, 0.03 * alpha) << (smith ? "smith" : "G=1");
    EXPECT_NEAR(r.params.at("alpha_y"), alpha, 0.03 * alpha) << (smith ? "smith" : "G=1");
  }
}

TEST(MeasuredNdf, GonioCsvOfAnisotropicGgxRecoversBothWidths) {
  const double ax = 0.1, ay = 0.25, phi = 0.3;
  const MicrofacetBrdf g(std::make_shared<GgxDistribution>(ax, ay, phi),
                         std::make_shared<ConductorFresnel>(constant_index(1.6, 3.2)));
  const GonioData d = gonio_points(g);
  EXPECT_EQ(d.points.size(), 4000u);
  const GonioData back = parse_gonio_csv(encode_gonio_csv(d), "goni.csv");
  const ConductorFresnel f(constant_index(1.6, 3.2));
  for (bool smith : {false, true}) {
    EffectiveNdfOptions o;
    o.resolution = 513;
    o.smith = smith;
    const TabulatedNdf t = effective_ndf(back, f, o);
    const FitResult r = fit_ggx(t);
    std::printf(
        "[ CSV ggx %.2f x %.2f, G %s ] fitted alpha_x %.4f alpha_y %.4f phi %.4f "
        "(%+.2f%%, %+.2f%%), %zu of %zu disk nodes measured\n",
        ax, ay, smith ? "smith" : "1", r.params.at("alpha_x"), r.params.at("alpha_y"), r.phi,
        100 * (r.params.at("alpha_x") / ax - 1), 100 * (r.params.at("alpha_y") / ay - 1),
        measured_nodes(t), std::size_t(kPi / 4 * 513 * 513));
    EXPECT_NEAR(r.params.at("alpha_x"), ax, 0.03 * ax) << (smith ? "smith" : "G=1");
    EXPECT_NEAR(r.params.at("alpha_y"), ay, 0.03 * ay) << (smith ? "smith" : "G=1");
    EXPECT_NEAR(r.phi, phi, 0.02);
  }
}

TEST(MeasuredNdf, UnmeasuredNodesAreNaNAndIgnoredByTheFit) {
  // Bins with theta_h above ~22 deg (index >= 45) hold no data.
  const double alpha = 0.3;
  const MerlBrdf m = merl_of_ggx(alpha, 45);
  const ConductorFresnel f(constant_index(1.2, 3.5));
  EffectiveNdfOptions o;
  o.resolution = 257;
  const TabulatedNdf t = effective_ndf(m, f, o);
  std::size_t nan = 0, inside = 0;
  for (std::size_t iy = 0; iy < t.resolution(); ++iy)
    for (std::size_t ix = 0; ix < t.resolution(); ++ix) {
      const double x = t.node_x(ix), y = t.node_y(iy), r2 = x * x + y * y;
      if (r2 >= 1) {
        EXPECT_EQ(t.at(ix, iy), 0.0);
        continue;
      }
      ++inside;
      const bool far = std::asin(std::sqrt(r2)) > 24 * kPi / 180;
      if (std::isnan(t.at(ix, iy))) ++nan;
      if (far) {
        EXPECT_TRUE(std::isnan(t.at(ix, iy))) << x << " " << y;
      }
    }
  EXPECT_GT(nan, inside / 2);
  EXPECT_EQ(measured_nodes(t), inside - nan);
  const FitResult r = fit_ggx(t);
  std::printf("[ MERL ggx %.2f, theta_h > 22 deg unmeasured ] fitted alpha %.4f (%+.2f%%)\n", alpha,
              r.params.at("alpha_x"), 100 * (r.params.at("alpha_x") / alpha - 1));
  EXPECT_NEAR(r.params.at("alpha_x"), alpha, 0.03 * alpha);
  EXPECT_NEAR(r.params.at("alpha_y"), alpha, 0.03 * alpha);
  // Reading the same gaps as zeros instead would pull the fit far off.
  TabulatedNdf zeros = t;
  for (double& v : zeros.values())
    if (std::isnan(v)) v = 0;
  const FitResult z = fit_ggx(zeros);
  EXPECT_GT(std::abs(z.params.at("alpha_x") / alpha - 1), 0.1);
}

TEST(MeasuredNdf, CompareScoresTheRightPredictionAndRejectsAWrongOne) {
  const double ax = 0.1, ay = 0.25, phi = 0.3;
  const auto d = std::make_shared<GgxDistribution>(ax, ay, phi);
  const MicrofacetBrdf g(d, std::make_shared<ConductorFresnel>(constant_index(1.6, 3.2)));
  EffectiveNdfOptions o;
  o.resolution = 513;
  const TabulatedNdf measured =
      effective_ndf(gonio_points(g), ConductorFresnel(constant_index(1.6, 3.2)), o);
  const NdfComparison right = compare_ndfs(measured, tabulate(*d, "ggx", 1025));
  const NdfComparison wrong =
      compare_ndfs(measured, tabulate(GgxDistribution(2 * ax, ay, phi), "ggx", 1025));
  std::printf(
      "[ compare ] right: rel L2 %.4f, Hellinger %.4f, widths x %.4f y %.4f, scale %.4f; "
      "wrong: rel L2 %.4f, widths x %.4f\n",
      right.relative_l2, right.hellinger, right.alpha_x_ratio, right.alpha_y_ratio, right.scale,
      wrong.relative_l2, wrong.alpha_x_ratio);
  EXPECT_EQ(right.nodes, measured_nodes(measured));
  EXPECT_LT(right.relative_l2, 0.1);
  EXPECT_NEAR(right.alpha_x_ratio, 1, 0.03);
  EXPECT_NEAR(right.alpha_y_ratio, 1, 0.03);
  EXPECT_GT(wrong.relative_l2, 3 * right.relative_l2);
  EXPECT_NEAR(wrong.alpha_x_ratio, 2, 0.1);
  // A 1.5 deg instrument widens the prediction a little, never narrows it.
  const NdfComparison blurred = compare_ndfs(measured, tabulate(*d, "ggx", 1025), 1.5 * kPi / 180);
  EXPECT_GT(blurred.predicted_fit.params.at("alpha_x"), right.predicted_fit.params.at("alpha_x"));
}

TEST(MeasuredNdf, NaNSurvivesNpyAndPreviewShowsItGrey) {
  TabulatedNdf t = tabulate(GgxDistribution(0.2), "ggx", 65);
  t.meta.method = "measured";
  for (std::size_t ix = 0; ix < 65; ++ix) t.at(ix, 40) = std::numeric_limits<double>::quiet_NaN();
  const std::string path = ::testing::TempDir() + "microbrdf_nan_ndf.npy";
  write_ndf(t, path);
  const TabulatedNdf back = read_ndf(path);
  EXPECT_TRUE(std::isnan(back.at(32, 40)));
  EXPECT_EQ(back.at(32, 32), t.at(32, 32));
  EXPECT_EQ(back.meta.method, "measured");
  NdfPreviewOptions po;
  po.size = 65;
  po.zoom = true;
  const RgbImage img = render_ndf_preview(back, po);
  // Pixel of node row 40 (m_y = 0.25) at m_x ~ -0.69 (away from the zoom frame): unmeasured grey.
  const std::size_t py = 10 + static_cast<std::size_t>((1 - 0.25) / 2 * 65);
  const std::size_t px = 10 + 10;
  const std::uint8_t* c = &img.pixels[3 * (py * img.width + px)];
  EXPECT_EQ(c[0], 96);
  EXPECT_EQ(c[2], 104);
  std::remove(path.c_str());
  std::remove((::testing::TempDir() + "microbrdf_nan_ndf.json").c_str());
}
