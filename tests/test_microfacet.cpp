// Beckmann and GGX distributions: normalisation, Smith G1, visible-normal sampling.
#include <cstdio>

#include "microbrdf/error.hpp"
#include "microbrdf/microfacet.hpp"
#include "test_microfacet_common.hpp"

using namespace microbrdf;
using mtest::Chart;
using mtest::direction;

namespace {

struct Case {
  const char* model;
  double ax, ay, phi;
};

std::shared_ptr<MicrofacetDistribution> make(const Case& c) {
  return make_distribution(NdfSpec{c.model, c.ax, c.ay, c.phi, 0, 0, 0, {}});
}

std::vector<Case> normalisation_cases() {
  std::vector<Case> v;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (const char* m : {"beckmann", "ggx"}) {
    for (double a : {0.005, 0.01, 0.05, 0.2, 0.5, 1.0}) v.push_back({m, a, a, 0});
    for (int k = 0; k < 6; ++k) {  // random anisotropy and rotation, alphas log-uniform 0.005..1
      double ax = 0.005 * std::pow(200.0, u(rng)), ay = 0.005 * std::pow(200.0, u(rng));
      v.push_back({m, ax, ay, 2 * mtest::kPi * u(rng)});
    }
  }
  return v;
}

}  // namespace

TEST(microfacet, NdfIntegratesToOne) {
  double worst = 0;
  for (const auto& c : normalisation_cases()) {
    auto d = make(c);
    Chart chart(mtest::lobe_stretch(c.ax, c.ay, c.phi));
    double i = chart.integrate([&](const Vec3& m) { return d->D(m) * m.z(); });
    EXPECT_NEAR(i, 1.0, 1e-4) << d->describe();
    worst = std::max(worst, std::abs(i - 1));
  }
  std::printf("max |integral D(m)(m.n) dw - 1| over %zu Beckmann/GGX cases: %.2e\n",
              normalisation_cases().size(), worst);
}

TEST(microfacet, NdfIntegratesToOnePlainSphericalGrid) {
  // Independent of the chart: plain Gauss-Legendre in cos(theta) x midpoint phi, for moderate
  // alphas.
  for (const Case& c : {Case{"beckmann", 0.3, 0.3, 0}, Case{"ggx", 0.3, 0.15, 0.4},
                        Case{"ggx", 1.0, 1.0, 0}, Case{"beckmann", 0.8, 0.4, 1.0}}) {
    auto d = make(c);
    Chart plain(Eigen::Matrix3d::Identity());
    EXPECT_NEAR(plain.integrate([&](const Vec3& m) { return d->D(m) * m.z(); }, 1024, 512), 1.0,
                1e-4)
        << d->describe();
  }
}

TEST(microfacet, ReferenceValuesTheory7) {
  auto v60 = direction(60, 0), v75 = direction(75, 0);
  BeckmannDistribution b(0.5);
  GgxDistribution g(0.5);
  EXPECT_NEAR(b.lambda(v60), 0.013162, 1e-6);
  EXPECT_NEAR(b.G1(v60), 0.987009, 1e-6);
  EXPECT_NEAR(g.lambda(v60), 0.161438, 1e-6);
  EXPECT_NEAR(g.G1(v60), 0.861002, 1e-6);
  EXPECT_NEAR(BeckmannDistribution(0.3077).G1(v75), 0.959059, 1e-6);
  EXPECT_NEAR(GgxDistribution(0.3077).G1(v75), 0.792791, 1e-6);
  auto m20 = direction(20, 33);
  EXPECT_NEAR(b.D(m20), 0.961248, 1e-6);
  EXPECT_NEAR(g.D(m20), 0.697658, 1e-6);
}

TEST(microfacet, SmithG1MatchesProjectedAreaQuadrature) {
  // G1(v) = (v.n) / integral D <v.m>+ dw (Heitz 2014), for anisotropic rotated lobes.
  for (const Case& c : {Case{"beckmann", 0.2, 0.5, 0.3}, Case{"ggx", 0.2, 0.5, 0.3},
                        Case{"ggx", 0.02, 0.6, -1.1}, Case{"beckmann", 0.7, 0.05, 2.0}}) {
    auto d = make(c);
    Chart chart(mtest::lobe_stretch(c.ax, c.ay, c.phi));
    for (double th : {0.0, 30.0, 60.0, 80.0, 88.0})
      for (double ph : {0.0, 50.0, 135.0}) {
        Vec3 v = direction(th, ph);
        double sigma = chart.integrate(
            [&](const Vec3& m) { return d->D(m) * std::max(0.0, v.dot(m)); }, 384, 384);
        EXPECT_NEAR(d->projected_area(v) / sigma, 1.0, 2e-5)
            << d->describe() << " view " << th << "," << ph;
      }
  }
}

TEST(microfacet, G1Bounds) {
  for (const char* m : {"beckmann", "ggx"}) {
    auto d = make({m, 0.3, 0.1, 0.5});
    EXPECT_EQ(d->G1(Vec3(0, 0, 1)), 1.0);
    for (double th = 0; th < 90; th += 7) {
      double g = d->G1(direction(th, 20));
      EXPECT_LE(g, 1.0);
      EXPECT_GT(g, 0.0);
    }
    EXPECT_EQ(d->G1(direction(30, 0), direction(80, 180)), 0.0);  // back-facing microfacet
  }
}

TEST(microfacet, WeakWhiteFurnace) {
  // integral G1(v) D(m) <v.m>+ dw / (v.n) = 1 (Heitz 2014).
  for (const Case& c : {Case{"beckmann", 0.3, 0.3, 0}, Case{"ggx", 0.3, 0.1, 0.7},
                        Case{"ggx", 0.01, 0.01, 0}, Case{"beckmann", 1.0, 0.5, 0.2}}) {
    auto d = make(c);
    Chart chart(mtest::lobe_stretch(c.ax, c.ay, c.phi));
    for (double th : {0.0, 45.0, 75.0, 89.0}) {
      Vec3 v = direction(th, 30);
      double i = chart.integrate(
          [&](const Vec3& m) { return d->G1(v, m) * d->D(m) * std::max(0.0, v.dot(m)); });
      EXPECT_NEAR(i / v.z(), 1.0, 1e-3) << d->describe() << " theta_v " << th;
    }
  }
}

TEST(microfacet, VisibleNormalSamplingChiSquare) {
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(0, 1);
  int cases = 0;
  for (const Case& c : {Case{"beckmann", 0.3, 0.3, 0}, Case{"beckmann", 0.1, 0.4, 0.6},
                        Case{"beckmann", 0.01, 0.01, 0}, Case{"ggx", 0.3, 0.3, 0},
                        Case{"ggx", 0.5, 0.1, -0.9}, Case{"ggx", 0.01, 0.02, 0.3}}) {
    auto d = make(c);
    Chart chart(mtest::lobe_stretch(c.ax, c.ay, c.phi));
    for (auto [th, ph] : {std::pair{0.0, 0.0}, {40.0, 20.0}, {75.0, 200.0}, {89.0, 100.0}}) {
      Vec3 v = direction(th, ph);
      std::vector<Vec3> s(200000);
      for (auto& m : s) {
        m = d->sample_visible(v, u(rng), u(rng));
        ASSERT_GT(m.z(), 0);
        ASSERT_NEAR(m.norm(), 1.0, 1e-12);
        ASSERT_GE(v.dot(m), -1e-12);
      }
      // 24 cases tested together at 1% overall significance (Bonferroni: 0.01/24 each).
      auto r = mtest::chi_square(
          chart, s, [&](const Vec3& m) { return d->pdf_visible(v, m); }, 0.01 / 24);
      EXPECT_NEAR(r.total_expected, 1.0, 1e-3) << d->describe();
      EXPECT_LT(r.chi2, r.critical) << d->describe() << " view " << th << "; dof " << r.dof;
      if (th == 89.0)
        std::printf("%-42s view %4.0f deg: chi2 %.1f, dof %d, critical %.1f\n",
                    d->describe().c_str(), th, r.chi2, r.dof, r.critical);
      ++cases;
    }
  }
  EXPECT_EQ(cases, 24);
}

TEST(microfacet, SamplingCatchesAWrongPdf) {
  // The chi-square test must be able to fail: compare GGX samples against a Beckmann pdf.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  GgxDistribution g(0.3);
  BeckmannDistribution b(0.3);
  Vec3 v = direction(40, 0);
  std::vector<Vec3> s(100000);
  for (auto& m : s) m = g.sample_visible(v, u(rng), u(rng));
  auto r = mtest::chi_square(Chart(mtest::lobe_stretch(0.3, 0.3, 0)), s,
                             [&](const Vec3& m) { return b.pdf_visible(v, m); });
  EXPECT_GT(r.chi2, r.critical);
}

TEST(microfacet, NdfSamplingMatchesDcos) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  for (const char* m : {"beckmann", "ggx"}) {
    auto d = make({m, 0.2, 0.6, 0.3});
    std::vector<Vec3> s(200000);
    for (auto& x : s) x = d->sample(u(rng), u(rng));
    auto r = mtest::chi_square(Chart(mtest::lobe_stretch(0.2, 0.6, 0.3)), s,
                               [&](const Vec3& x) { return d->pdf(x); });
    EXPECT_LT(r.chi2, r.critical) << m;
  }
}

TEST(microfacet, RotationTurnsTheLobe) {
  GgxDistribution a(0.1, 0.4, 0), b(0.1, 0.4, 0.5);
  BeckmannDistribution c(0.1, 0.4, 0), e(0.1, 0.4, 0.5);
  for (double th : {10.0, 30.0, 60.0})
    for (double ph : {0.0, 40.0, 123.0}) {
      Vec3 m = direction(th, ph), mr = direction(th, ph + 0.5 * 180 / mtest::kPi);
      EXPECT_NEAR(b.D(mr), a.D(m), 1e-12 * a.D(m));
      EXPECT_NEAR(e.D(mr), c.D(m), 1e-12 * c.D(m));
      EXPECT_NEAR(b.lambda(mr), a.lambda(m), 1e-12);
      EXPECT_NEAR(e.lambda(mr), c.lambda(m), 1e-12);
    }
}

TEST(microfacet, BadParameters) {
  EXPECT_THROW(make_distribution(NdfSpec{"phong", 0.1, 0.1, 0, 0, 0, 0, {}}), InputError);
  EXPECT_THROW(make_distribution(NdfSpec{"ggx", 0.0, 0.1, 0, 0, 0, 0, {}}), InputError);
  EXPECT_THROW(make_distribution(NdfSpec{"ggx", 0.1, 0.1, 0, 0.1, 0, 0, {}}), InputError);
  EXPECT_THROW(make_distribution(NdfSpec{"ellipsoid", 0.1, 0.1, 0.3, 0, 0, 0, {}}), InputError);
}

TEST(microfacet, TabulateOnTheDisk) {
  GgxDistribution g(0.3, 0.2, 0.4);
  auto t = tabulate(g, "ggx", 257);
  EXPECT_NEAR(t.integral(), 1.0, 1e-12);
  // Well-resolved lobe: the raw node sum was already ~1, so the values are D(m) itself.
  Vec3 m = direction(10, 30);
  EXPECT_NEAR(t.eval(m) / g.D(m), 1.0, 2e-3);
  EllipsoidDistribution e({0.1, 0.1, 0.2, 0, 0});
  auto te = tabulate(e, "ellipsoid", 513);
  EXPECT_LT((te.peak() - e.peak()).norm(), 2 * te.spacing());
}
