// Ellipsoid NDF (Dong 2015 eqs. 10-14; docs/theory.md §1).
#include <cstdio>

#include "test_microfacet_common.hpp"

using namespace microbrdf;
using mtest::Chart;
using mtest::direction;

namespace {

// Chart stretch for an ellipsoid: A^T = R^T S, made deliberately imperfect (factors 1.7, 0.6).
Eigen::Matrix3d ellipsoid_stretch(const EllipsoidDistribution& e) {
  const auto& p = e.params();
  return e.R().transpose() *
         Eigen::DiagonalMatrix<double, 3>(1.7 * p.alpha_x, 0.6 * p.alpha_y, 1.0).toDenseMatrix();
}

std::vector<EllipsoidParams> random_params(int n, unsigned seed, double max_tilt_deg = 40) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<EllipsoidParams> v;
  const double t = max_tilt_deg * mtest::kPi / 180;
  for (int k = 0; k < n; ++k) {
    v.push_back({0.005 * std::pow(200.0, u(rng)), 0.005 * std::pow(200.0, u(rng)),
                 t * (2 * u(rng) - 1), t * (2 * u(rng) - 1), 2 * mtest::kPi * u(rng)});
  }
  return v;
}

// Sigma+ by quadrature: integral D <u.m>+ dw.
double sigma_quad(const EllipsoidDistribution& e, const Vec3& u) {
  Chart c(ellipsoid_stretch(e));
  return c.integrate([&](const Vec3& m) { return e.D(m) * std::max(0.0, u.dot(m)); }, 384, 384);
}

}  // namespace

TEST(ellipsoid, ReducesToGgxAnisoWhenRIsIdentity) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(0, 1);
  double worst = 0;
  for (double ax : {0.005, 0.1, 0.37, 1.0})
    for (double ay : {0.02, 0.37, 0.8}) {
      EllipsoidDistribution e({ax, ay, 0, 0, 0});
      GgxDistribution g(ax, ay, 0);
      for (int k = 0; k < 200; ++k) {
        Vec3 m = direction(89.9 * u(rng), 360 * u(rng));
        double rel = std::abs(e.D(m) - g.D(m)) / g.D(m);
        worst = std::max(worst, rel);
        EXPECT_LT(rel, 1e-12);
        EXPECT_NEAR(e.lambda(m), g.lambda(m), 1e-12 * (1 + g.lambda(m)));
        EXPECT_NEAR(e.G1(m), g.G1(m), 1e-12);
      }
    }
  std::printf("ellipsoid (R = I) vs GGX-aniso: max relative difference in D %.2e\n", worst);
  // Isotropic: GGX with a single alpha.
  EllipsoidDistribution e({0.25, 0.25, 0, 0, 0});
  GgxDistribution g(0.25);
  for (double th : {0.0, 10.0, 45.0, 80.0})
    EXPECT_NEAR(e.D(direction(th, 17)), g.D(direction(th, 17)), 1e-12 * g.D(direction(th, 17)));
}

TEST(ellipsoid, ThetaZRotatesAxesByMinusThetaZ) {
  // R = Rz(theta_z): GGX-aniso with phi = -theta_z (documented convention).
  EllipsoidDistribution e({0.1, 0.4, 0, 0, 0.6});
  GgxDistribution g(0.1, 0.4, -0.6);
  for (double th : {5.0, 30.0, 70.0})
    for (double ph : {0.0, 77.0, 200.0}) {
      Vec3 m = direction(th, ph);
      EXPECT_NEAR(e.D(m), g.D(m), 1e-12 * g.D(m));
      EXPECT_NEAR(e.lambda(m), g.lambda(m), 1e-12);
    }
}

TEST(ellipsoid, IntegratesToOneRandomRotations) {
  double worst = 0;
  auto ps = random_params(30, 99);
  for (double a : {0.005, 0.05, 1.0}) ps.push_back({a, a, 0.3, -0.2, 1.0});
  ps.push_back({0.005, 1.0, 0.6, 0.5, 0.1});
  for (const auto& p : ps) {
    EllipsoidDistribution e(p);
    Chart c(ellipsoid_stretch(e));
    double i = c.integrate([&](const Vec3& m) { return e.D(m) * m.z(); });
    EXPECT_NEAR(i, 1.0, 1e-4) << e.describe();
    worst = std::max(worst, std::abs(i - 1));
    // Mean normal (docs/theory.md §1.2): integral D m dw = A^T A n / |A n|^2.
    Vec3 mean(c.integrate([&](const Vec3& m) { return e.D(m) * m.x(); }),
              c.integrate([&](const Vec3& m) { return e.D(m) * m.y(); }),
              c.integrate([&](const Vec3& m) { return e.D(m) * m.z(); }));
    EXPECT_NEAR((mean - e.mean_normal()).norm(), 0, 1e-4) << e.describe();
  }
  std::printf(
      "max |integral D(m)(m.n) dw - 1| over %zu ellipsoids (alpha 0.005..1, random R): %.2e\n",
      ps.size(), worst);
}

TEST(ellipsoid, IntegratesToOnePlainSphericalGrid) {
  // Chart-independent check for moderate alphas: plain Gauss-Legendre x midpoint on the hemisphere.
  for (const EllipsoidParams& p :
       {EllipsoidParams{0.4, 0.3, 0.3, -0.2, 0.5}, EllipsoidParams{1.0, 0.6, 0.5, 0.4, 2.0}}) {
    EllipsoidDistribution e(p);
    Chart plain(Eigen::Matrix3d::Identity());
    EXPECT_NEAR(plain.integrate([&](const Vec3& m) { return e.D(m) * m.z(); }, 1024, 512), 1.0,
                1e-4);
  }
}

TEST(ellipsoid, PeakMovesWithThetaXAndThetaY) {
  for (auto [tx, ty] : {std::pair{0.2, 0.0}, {0.0, 0.2}, {-0.15, 0.1}}) {
    EllipsoidDistribution e({0.1, 0.2, tx, ty, 0.3});
    Vec3 expect = rotation_z(-0.3) * rotation_y(-ty) * rotation_x(-tx) * Vec3(0, 0, 1);  // R^T z
    EXPECT_NEAR((e.peak() - expect).norm(), 0, 1e-14);
    // Brute-force maximum on a fine (theta, phi) grid.
    double best = 0;
    Vec3 arg(0, 0, 1);
    for (int i = 0; i <= 600; ++i)
      for (int j = 0; j < 1440; ++j) {
        Vec3 m = direction(30.0 * i / 600, 0.25 * j);
        double d = e.D(m);
        if (d > best) best = d, arg = m;
      }
    EXPECT_LT(std::acos(std::min(1.0, arg.dot(expect))), 0.1 * mtest::kPi / 180) << tx << " " << ty;
    EXPECT_GT(e.D(expect), 2 * e.D(Vec3(0, 0, 1)));
    // m* = R^T z: theta_x > 0 tilts the peak towards +y, theta_y > 0 towards -x.
    if (tx > 0 && ty == 0) {
      EXPECT_GT(arg.y(), 0);
    }
    if (ty > 0 && tx == 0) {
      EXPECT_LT(arg.x(), 0);
    }
  }
}

TEST(ellipsoid, ShadowingEq14) {
  for (const auto& p : random_params(8, 5, 35)) {
    EllipsoidDistribution e(p);
    EXPECT_NEAR(e.G1(Vec3(0, 0, 1)), 1.0, 1e-15) << e.describe();
    EXPECT_NEAR(e.projected_area(Vec3(0, 0, 1)), 1.0, 1e-14);
    for (double th : {0.0, 20.0, 50.0, 70.0, 85.0})
      for (double ph : {0.0, 100.0, 250.0}) {
        Vec3 u = direction(th, ph);
        double g = e.G1(u);
        EXPECT_LE(g, 1.0);
        EXPECT_GT(g, 0.0);
        // Eq. 14 before the clamp, written out from the paper.
        const Eigen::Matrix3d& a = e.A();
        Vec3 an = a * Vec3(0, 0, 1), au = a * u;
        double eq14 = 2 * an.squaredNorm() * u.z() / (au.norm() * an.norm() + au.dot(an));
        EXPECT_NEAR(g, std::min(1.0, eq14), 1e-13);
      }
  }
  // Unclamped eq. 14 (= (u.n)/sigma+) against the projected-area quadrature, incl. G1 > 1 cases.
  int above_one = 0;
  for (const auto& p : random_params(4, 17, 40)) {
    EllipsoidDistribution e(p);
    for (double th : {30.0, 60.0, 80.0})
      for (double ph : {45.0, 225.0}) {
        Vec3 u = direction(th, ph);
        double s = sigma_quad(e, u);
        EXPECT_NEAR(e.projected_area(u) / s, 1.0, 1e-5) << e.describe() << " u " << th << "," << ph;
        if (u.z() / s > 1) ++above_one;
      }
  }
  std::printf("unclamped G1 > 1 (skewed ellipsoid) in %d of 24 (A, u) pairs\n", above_one);
}

TEST(ellipsoid, WeakWhiteFurnace) {
  // integral G1u(v) D(m) <v.m>+ dw / (v.n) = 1 with the unclamped G1; the clamped G1 gives the same
  // wherever G1 <= 1.
  double worst = 0;
  for (const auto& p : random_params(6, 23, 30)) {
    EllipsoidDistribution e(p);
    Chart c(ellipsoid_stretch(e));
    for (double th : {0.0, 45.0, 75.0, 88.0}) {
      Vec3 v = direction(th, 60);
      double gu = 1.0 / (1.0 + e.lambda(v));
      double i = c.integrate([&](const Vec3& m) { return e.D(m) * std::max(0.0, v.dot(m)); });
      EXPECT_NEAR(gu * i / v.z(), 1.0, 1e-3) << e.describe() << " theta_v " << th;
      worst = std::max(worst, std::abs(gu * i / v.z() - 1));
      if (gu <= 1) {
        double ic = c.integrate(
            [&](const Vec3& m) { return e.G1(v, m) * e.D(m) * std::max(0.0, v.dot(m)); });
        EXPECT_NEAR(ic / v.z(), 1.0, 1e-3);
      }
    }
  }
  std::printf("ellipsoid weak white furnace: max |integral - 1| = %.2e\n", worst);
}

TEST(ellipsoid, VisibleNormalSamplingChiSquare) {
  std::mt19937_64 rng(777);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<EllipsoidParams> ps = {{0.3, 0.3, 0.3, 0.0, 0.0},
                                     {0.1, 0.5, 0.2, -0.3, 0.8},
                                     {0.02, 0.05, -0.25, 0.2, 2.0},
                                     {0.6, 0.2, 0.5, 0.4, -0.5}};
  int negative_vz = 0;
  for (const auto& p : ps) {
    EllipsoidDistribution e(p);
    Chart chart(ellipsoid_stretch(e));
    for (auto [th, ph] :
         {std::pair{0.0, 0.0}, {45.0, 30.0}, {80.0, 200.0}, {87.0, 90.0}, {87.0, 270.0}}) {
      Vec3 v = direction(th, ph);
      Vec3 av = e.A() * v, an = e.A() * Vec3(0, 0, 1);
      if (av.normalized().dot(an.normalized()) < 0) ++negative_vz;
      std::vector<Vec3> s(200000);
      for (auto& m : s) {
        m = e.sample_visible(v, u(rng), u(rng));
        ASSERT_GT(m.z(), -1e-12);
        ASSERT_GE(v.dot(m), -1e-12);
      }
      // 20 cases tested together at 1% overall significance (Bonferroni: 0.01/20 each).
      auto r = mtest::chi_square(
          chart, s, [&](const Vec3& m) { return e.pdf_visible(v, m); }, 0.01 / 20);
      EXPECT_NEAR(r.total_expected, 1.0, 1e-3) << e.describe() << " view " << th << "," << ph;
      EXPECT_LT(r.chi2, r.critical)
          << e.describe() << " view " << th << "," << ph << " dof " << r.dof;
      if (th == 87.0)
        std::printf("%-58s view (%2.0f,%3.0f): chi2 %.1f, dof %d, critical %.1f\n",
                    e.describe().c_str(), th, ph, r.chi2, r.dof, r.critical);
    }
  }
  std::printf("views with (Av).(An) < 0 (the skewed case of docs/theory.md §1.5): %d\n",
              negative_vz);
  EXPECT_GE(negative_vz, 1);
}

TEST(ellipsoid, NdfSamplingMatchesDcos) {
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> u(0, 1);
  EllipsoidDistribution e({0.2, 0.5, 0.3, 0.2, 0.7});
  std::vector<Vec3> s(200000);
  for (auto& m : s) m = e.sample(u(rng), u(rng));
  auto r =
      mtest::chi_square(Chart(ellipsoid_stretch(e)), s, [&](const Vec3& m) { return e.pdf(m); });
  EXPECT_LT(r.chi2, r.critical);
}
