// Sun 2002: free travel probability, Smith masking, the analytic BRDF in both forms, and the
// section 4 simulation. Reference values from docs/theory.md §5, §7 and §9.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "microbrdf/error.hpp"
#include "microbrdf/generate.hpp"
#include "microbrdf/sun2002.hpp"

using namespace microbrdf;
using namespace microbrdf::sun2002;

namespace {

constexpr double kDeg = M_PI / 180;

// The project's one conductor Fresnel (include/microbrdf/fresnel.hpp) with a constant index.
std::shared_ptr<const Fresnel> conductor(double eta, double kappa) {
  return std::make_shared<ConductorFresnel>(constant_index(eta, kappa));
}

Eigen::Vector3d dir(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Gamma_0 and Smith

TEST(sun2002, SunFtpLimitsAndEndpoints) {
  for (double s : {0.1, 0.5, 1.0, 5.0, 50.0}) {
    EXPECT_EQ(ftp(0, s), 1.0);
    EXPECT_EQ(ftp(M_PI / 2, s), 0.0);
    EXPECT_EQ(ftp(-0.1, s), 1.0);  // clamped
    double prev = 1;
    for (int d = 1; d < 90; ++d) {  // decreasing in theta
      double g = ftp(d * kDeg, s);
      EXPECT_LE(g, prev);
      EXPECT_GE(g, 0.0);
      prev = g;
    }
  }
  // s -> infinity: 1 (eq. 3.4.25).
  for (int d = 0; d <= 80; d += 10) EXPECT_NEAR(ftp(d * kDeg, 1e4), 1.0, 1e-12);
  // s -> 0: exp(-tan(theta) / (sqrt(2 pi) s)) (eq. 3.4.24, docs/theory.md §9.9) -> 0 off-normal.
  for (double d : {1.0, 2.0, 5.0}) {  // s << tan(theta)
    const double s = 1e-3, t = std::tan(d * kDeg);
    const double limit = std::exp(-t / (std::sqrt(2 * M_PI) * s));
    EXPECT_NEAR(std::log(ftp(d * kDeg, s)), std::log(limit),
                1e-2 * std::abs(std::log(limit)) + 1e-12)
        << d;
  }
  for (int d = 10; d < 90; d += 5) EXPECT_LT(ftp(d * kDeg, 1e-3), 1e-20);
  // Increasing in s at fixed theta.
  EXPECT_LT(ftp(60 * kDeg, 1), ftp(60 * kDeg, 2));
  EXPECT_THROW(ftp(0.3, 0), InputError);
  EXPECT_THROW(ftp(0.3, -1), InputError);
  EXPECT_THROW(ftp(NAN, 1), InputError);
}

TEST(sun2002, SunFtpNotesValuesAndSmithForm) {
  // docs/theory.md §5.2: Gamma_0 vs Smith-Beckmann G1 (alpha = 2/s).
  EXPECT_NEAR(ftp(60 * kDeg, 1), 0.530, 5e-4);
  EXPECT_NEAR(smith_g1(60 * kDeg, 1), 0.642, 5e-4);
  EXPECT_NEAR(ftp(60 * kDeg, 2), 0.781, 5e-4);
  EXPECT_NEAR(smith_g1(60 * kDeg, 2), 0.875, 5e-4);
  EXPECT_NEAR(ftp(75 * kDeg, 2), 0.500, 5e-4);
  EXPECT_NEAR(smith_g1(75 * kDeg, 2), 0.614, 5e-4);
  EXPECT_NEAR(ftp(85 * kDeg, 5), 0.419, 5e-4);
  EXPECT_NEAR(smith_g1(85 * kDeg, 5), 0.540, 5e-4);
  // docs/theory.md §7: Beckmann alpha = 0.5 (s = 4) at 60 deg; alpha = 0.3077 at 75 deg.
  EXPECT_NEAR(smith_lambda(60 * kDeg, 4), 0.013162, 2e-6);
  EXPECT_NEAR(smith_g1(60 * kDeg, 4), 0.987009, 2e-6);
  EXPECT_NEAR(smith_g1(75 * kDeg, 2 / 0.3077), 0.959059, 2e-6);
  // In Smith's variable a = s / (2 tan theta): Gamma_0 = exp(-exp(-a^2) / (2 sqrt(2 pi) a)).
  for (double s : {0.3, 1.0, 3.0})
    for (int d = 5; d < 90; d += 7) {
      const double a = s / (2 * std::tan(d * kDeg));
      EXPECT_NEAR(ftp(d * kDeg, s), std::exp(-std::exp(-a * a) / (2 * std::sqrt(2 * M_PI) * a)),
                  1e-13);
    }
  // k_tau scales the exponent.
  EXPECT_NEAR(ftp(50 * kDeg, 1, 0.5), std::sqrt(ftp(50 * kDeg, 1)), 1e-14);
}

TEST(sun2002, SunFtpSmithLambdaMatchesItsIntegral) {
  // Lambda = (1/mu) int_mu^inf (q - mu) p(q) dq, p Gaussian with std sqrt(2)/s, mu = cot(theta).
  for (double s : {0.25, 1.0, 4.0})
    for (int d : {10, 40, 70, 85}) {
      const double mu = 1 / std::tan(d * kDeg), sd = std::sqrt(2.0) / s;
      double sum = 0;
      const int n = 200000;
      const double hi = mu + 12 * sd, dq = (hi - mu) / n;
      for (int i = 0; i < n; ++i) {
        const double q = mu + (i + 0.5) * dq;
        sum += (q - mu) * std::exp(-q * q / (2 * sd * sd)) / (std::sqrt(2 * M_PI) * sd) * dq;
      }
      EXPECT_NEAR(smith_lambda(d * kDeg, s), sum / mu, 1e-7 + 1e-6 * sum / mu) << s << " " << d;
      EXPECT_NEAR(smith_at_mean_plane(d * kDeg, s), std::pow(0.5, sum / mu), 1e-6);
    }
  EXPECT_EQ(smith_g1(0, 1), 1.0);
  EXPECT_EQ(smith_g1(M_PI / 2, 1), 0.0);
}

TEST(sun2002, SunBrdfBeckmannNdfIsNormalised) {
  for (double s : {0.5, 2.0, 20.0}) {
    // In slope space D cos d(omega) = p(slope) d^2 slope; integrate over theta_h directly.
    const int n = 20000;
    double sum = 0;
    for (int i = 0; i < n; ++i) {
      const double th = (i + 0.5) * (M_PI / 2) / n;
      sum +=
          beckmann_ndf(std::cos(th), s) * std::cos(th) * std::sin(th) * (M_PI / 2) / n * 2 * M_PI;
    }
    EXPECT_NEAR(sum, 1.0, 1e-6) << s;
  }
}

// ---------------------------------------------------------------------------------------------
// The BRDF

TEST(sun2002, SunBrdfExactConductorFresnelOfTheTest) {
  // docs/theory.md §5.4 values, through the shared Fresnel the Sun BRDF uses.
  const double v[] = {0.6127, 0.6113, 0.6055, 0.5887, 0.5683, 0.6826};
  const int a[] = {0, 30, 45, 60, 75, 85};
  const auto f = conductor(2.76, 3.79);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(f->eval(std::cos(a[i] * kDeg), 555e-9), v[i], 1e-4);
  EXPECT_NEAR(conductor(1, 2)->eval(std::cos(75 * kDeg), 555e-9), 0.6244, 1e-4);
  EXPECT_NEAR(conductor(2.95, 2.93)->eval(1, 555e-9), 0.5121, 1e-4);
}

TEST(sun2002, SunBrdfReciprocity) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  const auto Fp = conductor(1.02, 2.577);
  const Fresnel* F = Fp.get();
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d wi = dir(std::acos(u(rng)), 2 * M_PI * u(rng));
    const Eigen::Vector3d wo = dir(std::acos(u(rng)), 2 * M_PI * u(rng));
    const double s = 0.3 + 10 * u(rng);
    for (auto form : {BrdfForm::AsPublished, BrdfForm::Standard}) {
      const double f1 = brdf(wi, wo, s, form, F), f2 = brdf(wo, wi, s, form, F);
      EXPECT_NEAR(f1, f2, 1e-12 * std::max(1.0, std::abs(f1)));
      EXPECT_GE(f1, 0.0);
    }
  }
}

TEST(sun2002, SunBrdfPublishedOverStandardRatio) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  const auto Fp = conductor(0.2, 3.0);
  const Fresnel* F = Fp.get();
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d wi = dir(std::acos(u(rng)), 2 * M_PI * u(rng));
    const Eigen::Vector3d wo = dir(std::acos(u(rng)), 2 * M_PI * u(rng));
    const double s = 0.5 + 5 * u(rng);
    const double fp = brdf(wi, wo, s, BrdfForm::AsPublished, F);
    const double fs = brdf(wi, wo, s, BrdfForm::Standard, F);
    const Eigen::Vector3d h = (wi + wo).normalized();
    const double expected = h.z() * wi.z() * wo.z() / wi.dot(h);
    if (fs < 1e-300) continue;
    EXPECT_NEAR(fp / fs, expected, 1e-10 * expected);
    EXPECT_NEAR(published_over_standard(wi, wo), expected, 1e-14);
  }
  // docs/theory.md §5.2: 1 at normal specular, 0.866 at 30 deg specular, 0.5 at 60 deg specular.
  for (auto [d, r] : {std::pair{0.0, 1.0}, {30.0, 0.8660}, {60.0, 0.5}}) {
    const Eigen::Vector3d wi = dir(d * kDeg, 0), wo = dir(d * kDeg, M_PI);
    EXPECT_NEAR(published_over_standard(wi, wo), r, 1e-4);
  }
}

TEST(sun2002, SunBrdfFormulaDetailsAndHorizon) {
  // At normal incidence and normal viewing: R s^2 / (16 pi) (eq. 3.5.3, theta = delta = 0),
  // and the standard form gives R D(n) / 4 = R s^2 / (16 pi) too.
  const Eigen::Vector3d z(0, 0, 1);
  for (double s : {0.5, 2.0, 10.0}) {
    const double expect = s * s / (16 * M_PI) * ftp(0, s) * ftp(0, s);
    EXPECT_NEAR(brdf(z, z, s, BrdfForm::AsPublished), expect, 1e-14 * expect);
    EXPECT_NEAR(brdf(z, z, s, BrdfForm::Standard), expect, 1e-14 * expect);
  }
  // The Fresnel factor is evaluated at cos(delta / 2) = wi . h.
  const Eigen::Vector3d wi = dir(50 * kDeg, 0), wo = dir(20 * kDeg, 2.0);
  struct Spy final : Fresnel {
    mutable double seen = -1, lambda = -1;
    double eval(double c, double wl) const override {
      seen = c;
      lambda = wl;
      return 0.25;
    }
    std::string describe() const override { return "spy"; }
  } spy;
  const double f = brdf(wi, wo, 1.5, BrdfForm::Standard, &spy, 633e-9);
  const double seen = spy.seen;
  EXPECT_EQ(spy.lambda, 633e-9);
  EXPECT_NEAR(seen, std::cos(0.5 * std::acos(wi.dot(wo))), 1e-14);
  EXPECT_NEAR(f, 0.25 * brdf(wi, wo, 1.5, BrdfForm::Standard), 1e-15);
  // Below or at the horizon: 0. Unnormalised inputs are fine.
  EXPECT_EQ(brdf(dir(30 * kDeg, 0), Eigen::Vector3d(0.3, 0, -0.1), 1, BrdfForm::Standard), 0.0);
  EXPECT_EQ(brdf(Eigen::Vector3d(1, 0, 0), z, 1, BrdfForm::AsPublished), 0.0);
  EXPECT_NEAR(brdf(3 * wi, 0.5 * wo, 1.5, BrdfForm::AsPublished),
              brdf(wi, wo, 1.5, BrdfForm::AsPublished), 1e-15);
  EXPECT_THROW(brdf(wi, wo, 0, BrdfForm::Standard), InputError);
}

TEST(sun2002, SunBrdfEnergyBoundWithUnitFresnel) {
  // R = 1 is the worst case. Sun's eq. 5.1 (integral of rho over the incident solid angle, no
  // cosine) <= 1, and the cosine-weighted albedo of both forms <= 1.
  for (double s : {0.5, 1.0, 2.0, 5.0, 10.0, 20.0})
    for (double d : {0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 85.0, 89.0}) {
      const double t = d * kDeg;
      const double eq51 = albedo(t, s, BrdfForm::AsPublished, nullptr, 555e-9, false, 128, 96);
      const double pub = albedo(t, s, BrdfForm::AsPublished, nullptr, 555e-9, true, 128, 96);
      const double stdf = albedo(t, s, BrdfForm::Standard, nullptr, 555e-9, true, 128, 96);
      EXPECT_LE(eq51, 1 + 1e-9) << s << " " << d;
      EXPECT_LE(pub, eq51 + 1e-12) << s << " " << d;
      EXPECT_LE(stdf, 1 + 1e-9) << s << " " << d;
      EXPECT_GE(pub, 0.0);
    }
  // Smooth surface seen from the normal: Gamma_0 ~ 1, so eq. 5.1 is an equality.
  EXPECT_NEAR(albedo(0, 20, BrdfForm::AsPublished, nullptr, 555e-9, false), 1.0, 1e-6);
  EXPECT_NEAR(albedo(0, 20, BrdfForm::Standard, nullptr, 555e-9, true), 1.0, 1e-6);
  // The quadrature has converged (the u range of each azimuth stops at the horizon).
  for (double s : {0.5, 3.0, 20.0})
    for (double t : {0.0, 0.7, 1.3})
      EXPECT_NEAR(albedo(t, s, BrdfForm::Standard, nullptr, 555e-9, true, 128, 128),
                  albedo(t, s, BrdfForm::Standard, nullptr, 555e-9, true, 512, 256), 1e-8)
          << s << " " << t;
  // A metal reflects less than the mirror bound.
  const auto Fp = conductor(0.2, 3.0);
  const Fresnel* F = Fp.get();
  EXPECT_LT(albedo(0.3, 5, BrdfForm::Standard, F), albedo(0.3, 5, BrdfForm::Standard));
}

// ---------------------------------------------------------------------------------------------
// The simulation of section 4

namespace {

FtpSimParams small_params(double s, std::size_t crossings, std::uint64_t seed) {
  FtpSimParams p;
  p.s = s;
  p.crossings = crossings;
  p.seed = seed;
  p.profile_length = 16384;
  for (int d : {0, 30, 45, 60, 75, 90}) p.theta.push_back(d * kDeg);
  return p;
}

}  // namespace

TEST(sun2002, SunSimDeterministicAndBasicFacts) {
  const auto a = simulate_ftp(small_params(1, 3000, 5));
  const auto b = simulate_ftp(small_params(1, 3000, 5));
  const auto c = simulate_ftp(small_params(1, 3000, 6));
  ASSERT_EQ(a.points.size(), 6u);
  bool differ = false;
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    EXPECT_EQ(a.points[i].free, b.points[i].free);
    EXPECT_EQ(a.points[i].rays_leaving, b.points[i].rays_leaving);
    differ |= a.points[i].free != c.points[i].free;
  }
  EXPECT_TRUE(differ);
  EXPECT_GE(a.crossings, 3000u);
  EXPECT_EQ(a.excluded, 0u);
  EXPECT_NEAR(a.slope_rms, std::sqrt(2.0), 0.03 * std::sqrt(2.0));
  // theta = 0: every ray is free; theta = 90 deg: 0 (not simulated).
  EXPECT_EQ(a.points[0].gamma_leaving, 1.0);
  EXPECT_EQ(a.points[0].gamma_any, 1.0);
  EXPECT_EQ(a.points[0].rays, 2 * a.crossings);
  EXPECT_EQ(a.points.back().gamma_leaving, 0.0);
  EXPECT_EQ(a.points.back().rays, 0u);
  for (const auto& p : a.points) EXPECT_LE(p.gamma_any, p.gamma_leaving);
}

TEST(sun2002, SunSimFractionLeavingAboveFollowsRice) {
  // At a zero crossing the slope density is proportional to |q| p(q) (Rice), so the fraction of
  // rays whose start slope q (along the ray) is below mu = cot(theta) is 1 - exp(-a^2) / 2,
  // a = mu s / 2. Checks the crossing detection and the "leaving above" test.
  const auto r = simulate_ftp(small_params(2, 5000, 3));
  for (const auto& p : r.points) {
    if (p.rays == 0 || p.theta == 0) continue;
    const double a = 2 / (2 * std::tan(p.theta));
    const double expect = 1 - 0.5 * std::exp(-a * a);
    const double frac = double(p.rays_leaving) / double(p.rays);
    const double se = std::sqrt(expect * (1 - expect) / double(p.rays));
    EXPECT_NEAR(frac, expect, 5 * se + 0.004) << p.theta / kDeg;
  }
}

TEST(sun2002, SunSimBruteForceOnTheSameKindOfProfiles) {
  // An independent, plain implementation (every sample ahead checked, no block skipping) on
  // profiles from generate_profiles, against simulate_ftp: statistically equal.
  const double s = 1, theta = 55 * kDeg, spt = 16;
  ProfileParams pp;
  pp.n = 40000;
  pp.rows = 6;
  pp.dx = 1 / spt;
  pp.sigma = 1 / s;
  pp.tau = 1;
  pp.seed = 424242;
  const Surface prof = generate_profiles(pp);
  const double m = pp.dx / std::tan(theta);
  std::size_t rays = 0, leaving = 0, free = 0;
  const std::size_t margin = 12000;  // 6.5 sigma tan(55 deg) / dx < 12000
  for (std::size_t r = 0; r < pp.rows; ++r) {
    const double* z = prof.z.data() + r * pp.n;
    for (std::size_t j = margin; j + 1 < pp.n - margin; ++j) {
      if ((z[j] < 0) == (z[j + 1] < 0)) continue;
      const double xc = j + z[j] / (z[j] - z[j + 1]);
      for (int dir : {1, -1}) {
        ++rays;
        const std::size_t k0 = dir > 0 ? j + 1 : j;
        if (!(z[k0] < std::abs(double(k0) - xc) * m)) continue;
        ++leaving;
        bool blocked = false;
        for (long k = long(k0) + dir; k >= 0 && k < long(pp.n); k += dir)
          if (z[k] >= std::abs(double(k) - xc) * m) {
            blocked = true;
            break;
          }
        free += !blocked;
      }
    }
  }
  FtpSimParams p;
  p.s = s;
  p.theta = {theta};
  p.crossings = 8000;
  p.seed = 77;
  const auto sim = simulate_ftp(p);
  const double g_bf = double(free) / double(leaving);
  const double g_any_bf = double(free) / double(rays);
  const auto& q = sim.points[0];
  // Binomial error of the brute force (crossings nearly independent) plus the batch error.
  const double se_bf = std::sqrt(g_bf * (1 - g_bf) / double(leaving)) * 1.5;
  EXPECT_NEAR(q.gamma_leaving, g_bf, 4 * std::hypot(se_bf, q.se_leaving));
  EXPECT_NEAR(q.gamma_any, g_any_bf,
              4 * std::hypot(std::sqrt(g_any_bf * (1 - g_any_bf) / double(rays)) * 1.5, q.se_any));
}

TEST(sun2002, SunSimSmallRunAgreesWithTheLargeOne) {
  // Reference: `microbrdf sun simulate-ftp --s 0.1,0.25,0.5,1,2,5 --samples 100000 --seed 1`
  // (docs/sun2002.md), rays leaving above / any crossing, with their standard errors.
  struct Ref {
    double s, theta_deg, leaving, se_leaving, any, se_any;
  };
  const Ref refs[] = {
      {0.1, 9, 0.75756, 0.00169, 0.41468, 0.00098}, {0.25, 20, 0.79169, 0.00157, 0.44010, 0.00093},
      {1, 45, 0.89450, 0.00109, 0.54674, 0.00092},  {1, 60, 0.72002, 0.00183, 0.38941, 0.00104},
      {1, 75, 0.31490, 0.00212, 0.16039, 0.00109},  {5, 80, 0.86793, 0.00126, 0.51145, 0.00090}};
  for (const auto& ref : refs) {
    FtpSimParams p = small_params(ref.s, 5000, 99);
    p.theta = {ref.theta_deg * kDeg};
    const auto r = simulate_ftp(p);
    const auto& q = r.points[0];
    EXPECT_NEAR(q.gamma_leaving, ref.leaving, 4 * std::hypot(q.se_leaving, ref.se_leaving) + 1e-9)
        << "s " << ref.s << " theta " << ref.theta_deg;
    EXPECT_NEAR(q.gamma_any, ref.any, 4 * std::hypot(q.se_any, ref.se_any) + 1e-9)
        << "s " << ref.s << " theta " << ref.theta_deg;
  }
}

TEST(sun2002, SunSimBadParameters) {
  FtpSimParams p = small_params(1, 100, 1);
  p.s = 0;
  EXPECT_THROW(simulate_ftp(p), InputError);
  p = small_params(1, 100, 1);
  p.theta = {};
  EXPECT_THROW(simulate_ftp(p), InputError);
  p = small_params(1, 100, 1);
  p.theta = {1.7};
  EXPECT_THROW(simulate_ftp(p), InputError);
  p = small_params(1, 100, 1);
  p.samples_per_tau = 1;
  EXPECT_THROW(simulate_ftp(p), InputError);
  p = small_params(0.1, 100, 1);
  p.theta = {(90 - 1e-7) * kDeg};  // margin beyond 2^26 samples
  EXPECT_THROW(simulate_ftp(p), InputError);
}

TEST(sun2002, SunSimSlowFullExperimentMatchesTheDocs) {
  // The docs/sun2002.md agreement table: max |sim - Gamma_0| over theta (rays leaving above).
  struct Row {
    double s, max_diff;
  };
  const Row rows[] = {{0.1, 0.1931}, {0.25, 0.1949}, {0.5, 0.1952},
                      {1, 0.1943},   {2, 0.1940},    {5, 0.1941}};
  for (const auto& row : rows) {
    FtpSimParams p;
    p.s = row.s;
    p.crossings = 100000;
    p.seed = 1;
    for (int d = 0; d <= 90; ++d) p.theta.push_back(d * kDeg);
    const auto r = simulate_ftp(p);
    double mx = 0;
    for (const auto& q : r.points) {
      if (q.rays == 0) continue;
      mx = std::max(mx, std::abs(q.gamma_leaving - ftp(q.theta, row.s)));
      EXPECT_LT(q.se_leaving, 0.01);
    }
    EXPECT_NEAR(mx, row.max_diff, 2e-3) << row.s;
    EXPECT_EQ(r.excluded, 0u);
  }
}
