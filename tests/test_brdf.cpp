// MicrofacetBrdf (Dong eq. 1): reciprocity, energy, sampling consistency, slices.
#include <cstdio>

#include "microbrdf/brdf_albedo.hpp"
#include "microbrdf/brdf_slice.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/microfacet_brdf.hpp"
#include "test_microfacet_common.hpp"

using namespace microbrdf;
using mtest::direction;

namespace {

std::vector<NdfSpec> specs() {
  return {NdfSpec{"beckmann", 0.2, 0.2, 0, 0, 0, 0, {}},
          NdfSpec{"ggx", 0.3, 0.1, 0.4, 0, 0, 0, {}},
          NdfSpec{"ellipsoid", 0.25, 0.4, 0, 0.2, -0.1, 0.5, {}},
          NdfSpec{"ggx", 0.05, 0.05, 0, 0, 0, 0, {}},
          NdfSpec{"beckmann", 1.0, 0.6, 1.0, 0, 0, 0, {}},
          NdfSpec{"ellipsoid", 0.8, 0.5, 0, 0.4, 0.3, 1.0, {}}};
}

MicrofacetBrdf make(const NdfSpec& s, std::shared_ptr<const Fresnel> f, bool separable = false) {
  return MicrofacetBrdf(make_distribution(s), std::move(f), separable);
}

}  // namespace

TEST(brdf, Reciprocity) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  auto cu = std::make_shared<ConductorFresnel>(metal("Cu"));
  for (const auto& s : specs())
    for (bool sep : {false, true}) {
      auto b = make(s, cu, sep);
      for (int k = 0; k < 300; ++k) {
        Vec3 wi = direction(89 * u(rng), 360 * u(rng)), wo = direction(89 * u(rng), 360 * u(rng));
        double lambda = (400 + 300 * u(rng)) * 1e-9;
        double f1 = b.eval(wi, wo, lambda), f2 = b.eval(wo, wi, lambda);
        EXPECT_NEAR(f1, f2, 1e-12 * std::max(1.0, f1)) << b.describe();
        EXPECT_GE(f1, 0);
      }
    }
}

TEST(brdf, AlbedoAtMostOne) {
  auto mirror = std::make_shared<PerfectMirrorFresnel>();
  auto au = std::make_shared<ConductorFresnel>(metal("Au"));
  double worst = 0;
  for (const auto& s : specs())
    for (bool sep : {false, true}) {
      auto b = make(s, mirror, sep);
      auto g = make(s, au, sep);
      for (double th : {0.0, 20.0, 45.0, 60.0, 75.0, 85.0, 89.0}) {
        for (double ph : {0.0, 120.0}) {
          Vec3 wi = direction(th, ph);
          double a = directional_albedo_sampled(b, wi, 550e-9, 128);
          EXPECT_LE(a, 1.0 + 1e-9) << b.describe() << " theta_i " << th;
          worst = std::max(worst, a);
          if (!sep) {
            EXPECT_LE(directional_albedo_sampled(g, wi, 550e-9, 128), a + 1e-9);
          }
          if (s.alpha_x >= 0.2 && s.alpha_y >= 0.2 &&
              th <= 70) {  // quadrature resolves these lobes
            EXPECT_NEAR(directional_albedo(b, wi, 550e-9, 64, 128), a, 2e-3)
                << b.describe() << " theta_i " << th;
          }
        }
      }
    }
  std::printf("largest directional albedo (F = 1) over the theta_i grid: %.9f\n", worst);
  // Nearly smooth: almost all light is reflected at normal incidence.
  auto smooth = make(NdfSpec{"ggx", 0.02, 0.02, 0, 0, 0, 0, {}}, mirror);
  EXPECT_GT(directional_albedo_sampled(smooth, Vec3(0, 0, 1), 550e-9), 0.999);
}

TEST(brdf, SampleWeightAndPdfConsistentWithEval) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> u(0, 1);
  auto al = std::make_shared<ConductorFresnel>(metal("Al"));
  for (const auto& s : specs()) {
    auto b = make(s, al);
    for (int k = 0; k < 500; ++k) {
      Vec3 wi = direction(85 * u(rng), 360 * u(rng));
      auto smp = b.sample(wi, u(rng), u(rng), 600e-9);
      if (!smp) continue;
      double f = b.eval(wi, smp->wo, 600e-9), p = b.pdf(wi, smp->wo);
      EXPECT_NEAR(smp->pdf, p, 1e-9 * p) << b.describe();
      EXPECT_NEAR(smp->weight, f * smp->wo.z() / p, 1e-9 * std::max(1.0, smp->weight))
          << b.describe();
    }
  }
}

TEST(brdf, SampledDirectionsFollowPdf) {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(0, 1);
  auto mirror = std::make_shared<PerfectMirrorFresnel>();
  const auto sp = specs();
  const int cases = 6;
  for (int c = 0; c < cases; ++c) {
    if (c == 3) continue;  // alpha 0.05: too narrow for an unstretched histogram
    auto b = make(sp[static_cast<std::size_t>(c)], mirror);
    Vec3 wi = direction(c % 2 ? 60 : 20, 30);
    std::vector<Vec3> s;
    s.reserve(200000);
    int absorbed = 0;
    while (s.size() + static_cast<std::size_t>(absorbed) < 200000) {
      auto smp = b.sample(wi, u(rng), u(rng), 550e-9);
      if (smp)
        s.push_back(smp->wo);
      else
        ++absorbed;
    }
    // The pdf integrates to the fraction of samples that are not absorbed.
    double kept = static_cast<double>(s.size()) / 200000;
    mtest::Chart plain(Eigen::Matrix3d::Identity());
    auto r = mtest::chi_square(
        plain, s, [&](const Vec3& wo) { return b.pdf(wi, wo) / kept; }, 0.01 / 5);
    EXPECT_LT(r.chi2, r.critical) << b.describe();
    EXPECT_NEAR(r.total_expected, 1.0, 5e-3) << b.describe();
  }
}

TEST(brdf, SpecularPeakInSlices) {
  auto b = make(NdfSpec{"ggx", 0.1, 0.1, 0, 0, 0, 0, {}},
                std::make_shared<ConductorFresnel>(metal("Cu")));
  auto in = tabulate_slice(b, 30 * mtest::kPi / 180, 555e-9, SlicePlane::In, 721);
  auto it = std::max_element(in.value.begin(), in.value.end());
  EXPECT_NEAR(in.angle_deg[static_cast<std::size_t>(it - in.value.begin())], 30.0, 0.3);
  auto out = tabulate_slice(b, 30 * mtest::kPi / 180, 555e-9, SlicePlane::Out, 721);
  auto jt = std::max_element(out.value.begin(), out.value.end());
  EXPECT_NEAR(out.angle_deg[static_cast<std::size_t>(jt - out.value.begin())], 0.0, 0.3);
  // At the mirror direction: f = F(30 deg) D(n) G2 / (4 cos^2 30).
  const auto& d = b.distribution();
  Vec3 wi(-0.5, 0, std::sqrt(0.75)), wo(0.5, 0, std::sqrt(0.75));
  double g2 = 1 / (1 + 2 * d.lambda(wi));
  double expect = fresnel_conductor(std::sqrt(0.75), metal("Cu").at(555e-9)) * d.D(Vec3(0, 0, 1)) *
                  g2 / (4 * 0.75);
  EXPECT_NEAR(b.eval(wi, wo, 555e-9), expect, 1e-12 * expect);
  EXPECT_NEAR(d.D(Vec3(0, 0, 1)), 1 / (mtest::kPi * 0.01), 1e-9);
}
