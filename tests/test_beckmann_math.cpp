// The Beckmann special functions (src/models/beckmann_math.hpp) against long-double references:
// erfcx, erfc, the Gaussian quantile, Smith's Lambda and the visible-slope quantile.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "models/beckmann_math.hpp"

namespace bm = microbrdf::beckmann;
using LD = long double;

namespace {

// Relative error, long-double reference.
double rel(double got, LD ref) { return double(std::fabs(LD(got) - ref) / std::fabs(ref)); }

// x in [-40, 40] with erfc(-x)/2 = u (mu = inf) or C(x) = u C(mu) (the visible-slope CDF), by
// bisection in long double (erfcl/expl); the upper half compares the mass above x.
LD slope_reference(double mu, double u) {
  const bool flat = std::isinf(mu);
  const LD h = flat ? 0 : LD(mu) * 0.886226925452758013649083741671L;  // mu sqrt(pi)/2
  auto cdf = [&](LD x) {
    return flat ? 0.5L * std::erfc(-x) : h * std::erfc(-x) + 0.5L * std::exp(-x * x);
  };
  // the mass above x, without cancellation against the total
  auto above = [&](LD x) {
    return flat ? 0.5L * std::erfc(x)
                : h * (std::erfc(x) - std::erfc(LD(mu))) -
                      0.5L * (std::exp(-x * x) - std::exp(-LD(mu) * mu));
  };
  const LD cmu = flat ? 1.0L : cdf(mu);
  LD lo = -40, hi = flat ? 40 : LD(mu);
  for (int i = 0; i < 120; ++i) {
    const LD m = 0.5L * (lo + hi);
    const bool right = u > 0.5 ? above(m) < (1 - LD(u)) * cmu : cdf(m) > LD(u) * cmu;
    (right ? hi : lo) = m;
  }
  return 0.5L * (lo + hi);
}

std::vector<double> unit_grid() {  // dense in (0, 1) with both tails
  std::vector<double> u;
  for (int i = 1; i < 4000; ++i) u.push_back(i / 4000.0);
  for (double e = 1e-3; e > 1e-30; e *= 0.37) u.push_back(e);
  for (double e = 1e-3; e > 1e-10; e *= 0.37) u.push_back(1 - e);
  return u;
}

}  // namespace

TEST(BeckmannMath, ErfcxMatchesLongDouble) {
  double worst = 0, at = 0;
  for (double x = 0; x < 30; x += 1.0 / 1024 + 1e-7) {  // crosses every interval edge
    const LD ref = std::exp(LD(x) * x) * std::erfc(LD(x));
    const double e = rel(bm::erfcx(x), ref);
    if (e > worst) worst = e, at = x;
  }
  for (double x = 30; x < 100; x += 0.37) {
    const LD ref = std::exp(LD(x) * x) * std::erfc(LD(x));
    worst = std::max(worst, rel(bm::erfcx(x), ref));
  }
  for (double x = 100; x < 1e150; x *= 1.7) {  // the asymptotic series, 5 terms (next < 1e-18)
    const LD y = 1 / (LD(x) * x);
    const LD s = 1 - y * (0.5L - y * (0.75L - y * (1.875L - y * 6.5625L)));
    const LD ref = s / (LD(x) * 1.77245385090551602729816748334L);
    worst = std::max(worst, rel(bm::erfcx(x), ref));
  }
  for (double x = -5; x < 0; x += 1.0 / 256 + 1e-7) {  // the reflection, for completeness
    const LD ref = std::exp(LD(x) * x) * std::erfc(LD(x));
    worst = std::max(worst, rel(bm::erfcx(x), ref));
  }
  std::printf("erfcx: max relative error %.3g (x = %g)\n", worst, at);
  EXPECT_LT(worst, 1e-15);
  EXPECT_EQ(bm::erfcx(INFINITY), 0.0);
  EXPECT_EQ(bm::erfcx(-INFINITY), INFINITY);
  EXPECT_TRUE(std::isnan(bm::erfcx(NAN)));
}

TEST(BeckmannMath, ErfcMatchesStdErfc) {
  double worst = 0, at = 0, worst_std = 0;
  for (double x = -6; x < 26.5; x += 1.0 / 512 + 1e-7) {
    const LD ref = std::erfc(LD(x));
    const double e = rel(bm::erfc(x), ref);
    if (e > worst) worst = e, at = x;
    worst_std = std::max(worst_std, rel(std::erfc(x), ref));
  }
  std::printf("erfc on [-6, 26.5]: max relative error %.3g (x = %g); std::erfc %.3g\n", worst, at,
              worst_std);
  EXPECT_LT(worst, 2e-15);
  EXPECT_EQ(bm::erfc(30), 0.0);
  EXPECT_EQ(bm::erfc(-30), 2.0);
  EXPECT_EQ(bm::erfc(INFINITY), 0.0);
  EXPECT_EQ(bm::erfc(-INFINITY), 2.0);
}

TEST(BeckmannMath, ExpMinusSquare) {
  double worst = 0;
  for (double x = -26.5; x < 26.5; x += 1.0 / 256 + 1e-7)  // exp(-x^2) normal
    worst = std::max(worst, rel(bm::exp_minus_sq(x), std::exp(-LD(x) * x)));
  EXPECT_LT(worst, 1e-15);
  EXPECT_EQ(bm::exp_minus_sq(1e200), 0.0);
}

TEST(BeckmannMath, ErfinvMatchesLongDouble) {
  // The polynomials of erfinv_u: relative error ~1e-15 wherever they answer.
  double worst = 0, at = 0;
  for (double u : unit_grid()) {
    if (u < 1.2e-25) continue;  // the fitted range
    const double g = bm::erfinv_u(u);
    ASSERT_TRUE(g == g) << u;
    const LD ref = slope_reference(INFINITY, u);
    const double e = double(std::fabs(g - ref) / std::max(std::fabs(ref), 1e-4L));
    if (e > worst) worst = e, at = u;
  }
  std::printf("erfinv: max relative error %.3g at u = %.17g\n", worst, at);
  EXPECT_LT(worst, 3e-15);
  EXPECT_TRUE(std::isnan(bm::erfinv_u(1e-30)));
}

TEST(BeckmannMath, GaussQuantileRoundTrips) {
  double worst = 0, worst_u = 0, at = 0;
  for (double u : unit_grid()) {
    const double x = bm::gauss_quantile(u);
    const LD ref = slope_reference(INFINITY, u);
    const double e = double(std::fabs(x - ref) / (1 + std::fabs(ref)));
    if (e > worst) worst = e, at = u;
    // back through the CDF: erfc(-x)/2 = u (the complement above 1/2)
    const LD back = u <= 0.5 ? 0.5L * std::erfc(-LD(x)) : 1 - 0.5L * std::erfc(LD(x));
    worst_u = std::max(worst_u,
                       double(std::fabs(back - u) / std::min(u, 1 - u)) / (1 + 2 * std::fabs(x)));
    if (u >= 0.5) {  // 1 - u is exact here
      EXPECT_EQ(x, -bm::gauss_quantile(1 - u)) << u;
    }
  }
  std::printf("gauss quantile: max error %.3g (1 + |x|) at u = %g, round trip %.3g\n", worst, at,
              worst_u);
  EXPECT_LT(worst, 3e-15);
  EXPECT_LT(worst_u, 1e-14);
  // Tails beyond the polynomials: finite and ordered.
  EXPECT_NEAR(bm::gauss_quantile(1e-40), double(slope_reference(INFINITY, 1e-40)), 1e-12);
  EXPECT_TRUE(std::isfinite(bm::gauss_quantile(0.0)));
  EXPECT_EQ(bm::gauss_quantile(0.0), bm::gauss_quantile(1e-300));  // u = 0 taken as 1e-300
}

TEST(BeckmannMath, SmithLambdaMatchesTheErfcFormula) {
  double worst = 0;
  for (double a = 1e-4; a < 40; a *= 1.01) {
    const LD ref = 0.5L * (std::exp(-LD(a) * a) / (LD(a) * 1.77245385090551602729816748334L) -
                           std::erfc(LD(a)));
    worst = std::max(worst, double(std::fabs(bm::smith_lambda(a) - ref) / (1 + ref)));
  }
  std::printf("Smith Lambda: max error %.3g (1 + Lambda)\n", worst);
  EXPECT_LT(worst, 1e-15);
  EXPECT_EQ(bm::smith_lambda(INFINITY), 0.0);
}

TEST(BeckmannMath, VisibleSlopeRoundTrips) {
  // The visible-slope quantile at many (mu, u) against the long-double bisection: converged to
  // 1e-10 (1 + |x|) (sample_visible promises ~1e-8), and monotone in u.
  double worst = 0, wmu = 0, wu = 0;
  int n = 0;
  for (double mu : {0.0, 1e-6, 1e-3, 0.01, 0.1, 0.3, 0.5,  0.7,  0.9,  1.0,   1.0001, 1.1, 1.3, 1.7,
                    2.0, 2.5,  3.0,  4.0,  5.0, 7.0, 10.0, 20.0, 50.0, 300.0, 1e4,    1e7, 2e8}) {
    double prev = -INFINITY;
    for (double u : unit_grid()) {
      if (u < 1e-25) continue;
      const double x = bm::visible_slope(mu, u);
      const LD ref = slope_reference(mu >= 1e8 ? INFINITY : mu, u);
      const double e = double(std::fabs(x - ref) / (1 + std::fabs(ref)));
      if (e > worst) worst = e, wmu = mu, wu = u;
      if (u > 1e-3 && u < 1 - 1e-3) {
        EXPECT_GE(x, prev) << "mu " << mu << " u " << u;
        prev = x;
      }
      EXPECT_LE(x, mu) << "mu " << mu << " u " << u;
      ++n;
    }
  }
  std::printf("visible slope: %d points, max error %.3g (1 + |x|) at mu %g, u %.17g\n", n, worst,
              wmu, wu);
  EXPECT_LT(worst, 1e-10);
  for (double mu : {0.0, 0.5, 3.0}) EXPECT_TRUE(std::isfinite(bm::visible_slope(mu, 0.0)));
}

TEST(BeckmannMath, VisibleSlopeStartIsClose) {
  // The tabulated start is within 1e-4 (1 + |x|) of the root (one Halley step then ends the
  // iteration) for most (mu, u); a performance property, asserted loosely.
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> un(0, 1);
  int close = 0, n = 0;
  for (int k = 0; k < 20000; ++k) {
    const double mu = k % 2 ? 3 * un(rng) : 1 / (1e-3 + un(rng)), u = un(rng);
    const double x = bm::visible_slope(mu, u), s = bm::visible_slope_start(mu, u);
    ASSERT_TRUE(std::isfinite(s)) << mu << " " << u;
    close += std::abs(s - x) <= 1e-4 * (1 + std::abs(x));
    ++n;
  }
  std::printf("visible slope start within 1e-4 (1 + |x|): %.4f of %d\n", double(close) / n, n);
  EXPECT_GT(close, 0.97 * n);
}
