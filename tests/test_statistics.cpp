// Statistics on surfaces with known answers: analytic surfaces, brute-force ACF, Gaussian
// random surfaces (acceptance: sigma 1%, tau 5%, slope 5% of sqrt(2) sigma / tau).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "microbrdf/generate.hpp"
#include "microbrdf/level.hpp"
#include "microbrdf/statistics.hpp"

using namespace microbrdf;

namespace {

// Central differences see sigma^2 (1 - exp(-4 d^2/tau^2)) / (2 d^2) (docs/theory.md §3.4).
double central_difference_slope(double sigma, double tau, double d) {
  return sigma * std::sqrt((1 - std::exp(-4 * d * d / (tau * tau))) / (2 * d * d));
}

}  // namespace

TEST(Statistics, MomentsOfKnownValues) {
  Surface s(4, 1, 1e-6, 1e-6);
  s.z = {1e-6, 2e-6, 3e-6, 4e-6};
  auto st = compute_stats(s);
  EXPECT_DOUBLE_EQ(st.mean, 2.5e-6);
  EXPECT_NEAR(st.sq, std::sqrt(1.25) * 1e-6, 1e-18);
  EXPECT_NEAR(st.sa, 1e-6, 1e-18);
  EXPECT_NEAR(st.skewness, 0, 1e-12);
  EXPECT_NEAR(st.kurtosis, 1.64, 1e-12);  // (0.0625*2+5.0625*2)/4 / 1.25^2
  EXPECT_DOUBLE_EQ(st.min, 1e-6);
  EXPECT_DOUBLE_EQ(st.max, 4e-6);
  EXPECT_NEAR(st.slope_rms_x, 1.0, 1e-12);  // a ramp of slope 1
}

TEST(Statistics, InvalidSamplesAreExcludedNotFilled) {
  Surface s(8, 8, 1e-6, 1e-6);
  for (std::size_t i = 0; i < s.size(); ++i)
    s.z[i] = 1e-6 * static_cast<double>(i % 8);  // slope 1 in x
  s.invalidate(10);
  s.invalidate(27);
  auto st = compute_stats(s);
  EXPECT_EQ(st.valid_count, 62u);
  EXPECT_NEAR(st.slope_rms_x, 1.0, 1e-12);  // no difference touches a hole
  EXPECT_NEAR(st.slope_rms_y, 0.0, 1e-12);
  EXPECT_EQ(st.slope_samples_x, 8u * 6u - 4u);  // each hole removes its two neighbours' stencils
}

TEST(Statistics, FftAutocorrelationMatchesBruteForceWithHoles) {
  GaussianSurfaceParams p;
  p.nx = 96;
  p.ny = 80;
  p.dx = 1e-7;
  p.dy = 1.3e-7;
  p.tau_x = 5e-7;
  p.tau_y = 8e-7;
  p.seed = 7;
  Surface s = generate_gaussian(p);
  std::mt19937 rng(3);
  for (int k = 0; k < 400; ++k) s.invalidate(rng() % s.size());
  auto acf = autocorrelation(s, 1);
  for (auto [lx, ly] :
       {std::pair{0L, 0L}, {1L, 0L}, {0L, 1L}, {5L, -3L}, {-7L, 4L}, {40L, 30L}, {-90L, 2L}}) {
    EXPECT_NEAR(acf.at(lx, ly), autocorrelation_direct(s, lx, ly), 1e-10) << lx << "," << ly;
  }
}

// compute_stats finds the radial 1/e crossing over a growing box of lags; the reference averages
// the whole lag grid of autocorrelation() in annuli, then finds the crossing. Short and long
// correlation lengths (the box must grow past 64 spacings for the second), with and without holes.
TEST(Statistics, RadialCorrelationLengthMatchesWholeGridAverage) {
  for (double tau_samples : {6.0, 90.0})
    for (bool holes : {false, true}) {
      GaussianSurfaceParams p;
      p.nx = 300;
      p.ny = 260;
      p.tau_x = tau_samples * p.dx;
      p.tau_y = 0.7 * tau_samples * p.dy;
      Surface s = generate_gaussian(p);
      if (holes)
        for (std::size_t i = 0; i < s.size(); i += 13) s.invalidate(i);
      const Autocorrelation acf = autocorrelation(s);
      RadialProfile whole;
      const double dr = std::min(s.dx, s.dy);
      std::vector<double> sum, cnt;
      for (long ly = 1 - static_cast<long>(s.ny); ly < static_cast<long>(s.ny); ++ly)
        for (long lx = 1 - static_cast<long>(s.nx); lx < static_cast<long>(s.nx); ++lx) {
          const double v = acf.at(lx, ly);
          if (!std::isfinite(v)) continue;
          const double r = std::sqrt(std::pow(static_cast<double>(lx) * s.dx, 2) +
                                     std::pow(static_cast<double>(ly) * s.dy, 2));
          const auto b = static_cast<std::size_t>(std::floor(r / dr + 0.5));
          if (b >= sum.size()) sum.resize(b + 1, 0.0), cnt.resize(b + 1, 0.0);
          sum[b] += v;
          cnt[b] += 1;
        }
      // First annulus whose mean falls to 1/e, interpolated linearly from the one before.
      double ref = std::nan("");
      double prev_r = 0, prev_v = 1;
      for (std::size_t b = 1; b < sum.size(); ++b) {
        if (cnt[b] == 0) continue;
        const double v = sum[b] / cnt[b], r = static_cast<double>(b) * dr;
        if (v <= std::exp(-1.0)) {
          ref = prev_r + (prev_v - std::exp(-1.0)) / (prev_v - v) * (r - prev_r);
          break;
        }
        prev_r = r;
        prev_v = v;
      }
      ASSERT_TRUE(std::isfinite(ref));
      EXPECT_NEAR(compute_stats(s).corr_length / ref, 1.0, 1e-9)
          << "tau " << tau_samples << " samples, holes " << holes;
    }
}

TEST(Statistics, SinusoidHasCosineAutocorrelation) {
  // z = A sin(2 pi x / P): ACF(l) = cos(2 pi l / P) (up to the finite-window edge effects).
  GratingParams g;
  g.nx = 2048;
  g.ny = 4;
  g.dx = 1e-7;
  g.period = 64 * g.dx;
  Surface s = generate_grating(g);
  auto acf = autocorrelation(s);
  EXPECT_NEAR(acf.at(16, 0), 0.0, 0.02);
  EXPECT_NEAR(acf.at(32, 0), -1.0, 0.02);
  EXPECT_NEAR(acf.at(64, 0), 1.0, 0.02);
  auto st = compute_stats(s);
  EXPECT_NEAR(st.sq, g.amplitude / std::sqrt(2.0), 1e-3 * g.amplitude);
}

TEST(Statistics, PsdIntegratesToVariance) {
  GaussianSurfaceParams p;
  p.nx = 256;
  p.ny = 256;
  p.tau_x = p.tau_y = 10 * p.dx;
  Surface s = generate_gaussian(p);
  auto psd = power_spectrum(s);
  // Ring integral: sum S(k) 2 pi k dk / (2 pi)^2 ~ sigma^2 (rings cut at the Nyquist circle
  // lose the corners, where a tau = 10-sample surface has no power).
  double dk = psd.k[1] - psd.k[0];
  double var = 0;
  for (std::size_t i = 0; i < psd.k.size(); ++i)
    var += psd.s[i] * 2 * M_PI * psd.k[i] * dk / (4 * M_PI * M_PI);
  EXPECT_NEAR(var, p.sigma * p.sigma, 0.03 * p.sigma * p.sigma);
  // Gaussian PSD: S(k) = pi tau^2 sigma^2 exp(-k^2 tau^2 / 4); compare near k = 1/tau.
  std::size_t i = static_cast<std::size_t>(std::lround((1.0 / p.tau_x) / dk)) - 1;
  double expect = M_PI * p.tau_x * p.tau_x * p.sigma * p.sigma *
                  std::exp(-psd.k[i] * psd.k[i] * p.tau_x * p.tau_x / 4);
  EXPECT_NEAR(psd.s[i] / expect, 1.0, 0.25);
}

// Acceptance 2: Gaussian surfaces, 1024^2, several seeds, tau of 10-50 samples, isotropic and
// anisotropic.
struct GaussCase {
  double tau_x_samples, tau_y_samples;
  std::uint64_t seed;
};
class GaussianStats : public ::testing::TestWithParam<GaussCase> {};

TEST_P(GaussianStats, SigmaTauSlopeMatchTheory) {
  const auto c = GetParam();
  GaussianSurfaceParams p;
  p.nx = p.ny = 1024;
  p.dx = p.dy = 110e-9;
  p.sigma = 0.2e-6;
  p.tau_x = c.tau_x_samples * p.dx;
  p.tau_y = c.tau_y_samples * p.dy;
  p.seed = c.seed;
  Surface s = generate_gaussian(p);
  auto st = compute_stats(s);
  EXPECT_NEAR(st.sq / p.sigma, 1.0, 0.01);
  EXPECT_NEAR(st.corr_length_x / p.tau_x, 1.0, 0.05);
  EXPECT_NEAR(st.corr_length_y / p.tau_y, 1.0, 0.05);
  // The continuum rms slope sqrt(2) sigma / tau, within 5% ...
  EXPECT_NEAR(st.slope_rms_x / (std::sqrt(2.0) * p.sigma / p.tau_x), 1.0, 0.05);
  EXPECT_NEAR(st.slope_rms_y / (std::sqrt(2.0) * p.sigma / p.tau_y), 1.0, 0.05);
  // ... and the central-difference expectation, tighter.
  EXPECT_NEAR(st.slope_rms_x / central_difference_slope(p.sigma, p.tau_x, p.dx), 1.0, 0.03);
  EXPECT_NEAR(st.slope_rms_y / central_difference_slope(p.sigma, p.tau_y, p.dy), 1.0, 0.03);
  if (c.tau_x_samples == c.tau_y_samples) {
    EXPECT_NEAR(st.corr_length / p.tau_x, 1.0, 0.05);
  }
  // Height moments of a Gaussian field scatter with the number of correlation areas.
  double areas = static_cast<double>(s.size()) * s.dx * s.dy / (M_PI * p.tau_x * p.tau_y);
  EXPECT_NEAR(st.skewness, 0.0, 4 * std::sqrt(6 / areas));
  EXPECT_NEAR(st.kurtosis, 3.0, 4 * std::sqrt(24 / areas));
}

INSTANTIATE_TEST_SUITE_P(Acceptance, GaussianStats,
                         ::testing::Values(GaussCase{10, 10, 1}, GaussCase{10, 10, 2},
                                           GaussCase{25, 25, 3}, GaussCase{50, 50, 4},
                                           GaussCase{50, 50, 5}, GaussCase{10, 40, 6},
                                           GaussCase{40, 15, 7}, GaussCase{20, 50, 8}));

// A true Gaussian process (no exact spectrum): single realisations scatter, the average over
// seeds converges to the same theory.
TEST(Statistics, GaussianProcessAveragedOverSeeds) {
  GaussianSurfaceParams p;
  p.nx = p.ny = 1024;
  p.tau_x = 20 * p.dx;
  p.tau_y = 12 * p.dy;
  p.exact_spectrum = false;
  double tx = 0, ty = 0, sx = 0, sy = 0;
  const int seeds = 4;
  for (int seed = 1; seed <= seeds; ++seed) {
    p.seed = static_cast<std::uint64_t>(seed);
    auto st = compute_stats(generate_gaussian(p));
    tx += st.corr_length_x / seeds;
    ty += st.corr_length_y / seeds;
    sx += st.slope_rms_x / seeds;
    sy += st.slope_rms_y / seeds;
  }
  EXPECT_NEAR(tx / p.tau_x, 1.0, 0.05);
  EXPECT_NEAR(ty / p.tau_y, 1.0, 0.05);
  EXPECT_NEAR(sx / central_difference_slope(p.sigma, p.tau_x, p.dx), 1.0, 0.05);
  EXPECT_NEAR(sy / central_difference_slope(p.sigma, p.tau_y, p.dy), 1.0, 0.05);
}

TEST(Statistics, SlowLargeAnisotropicGaussian) {
  GaussianSurfaceParams p;
  p.nx = p.ny = 2048;
  p.tau_x = 50 * p.dx;
  p.tau_y = 12 * p.dy;
  for (std::uint64_t seed : {11, 12, 13}) {
    p.seed = seed;
    auto st = compute_stats(generate_gaussian(p));
    EXPECT_NEAR(st.sq / p.sigma, 1.0, 0.01);
    EXPECT_NEAR(st.corr_length_x / p.tau_x, 1.0, 0.05);
    EXPECT_NEAR(st.corr_length_y / p.tau_y, 1.0, 0.05);
    EXPECT_NEAR(st.slope_rms_x / (std::sqrt(2.0) * p.sigma / p.tau_x), 1.0, 0.05);
    EXPECT_NEAR(st.slope_rms_y / (std::sqrt(2.0) * p.sigma / p.tau_y), 1.0, 0.05);
  }
}

TEST(Leveling, PlaneRemovalRecoversRoughness) {
  GaussianSurfaceParams p;
  p.nx = p.ny = 256;
  p.tau_x = p.tau_y = 8 * p.dx;
  Surface s = generate_gaussian(p);
  Surface tilted = s;
  for (std::size_t iy = 0; iy < s.ny; ++iy)
    for (std::size_t ix = 0; ix < s.nx; ++ix)
      tilted.at(ix, iy) +=
          5e-6 + 0.1 * static_cast<double>(ix) * s.dx - 0.2 * static_cast<double>(iy) * s.dy;
  tilted.invalidate(100);
  auto r = level_surface(tilted, LevelingSpec::parse("plane"));
  EXPECT_EQ(tilted.meta.leveling, "plane");
  EXPECT_GT(r.rms_before, 10 * r.rms_after);
  EXPECT_NEAR(r.rms_after / compute_stats(s).sq, 1.0, 0.01);
  EXPECT_TRUE(std::isnan(tilted.z[100]));
  // A pure quadratic is removed exactly by poly2 and not by a plane.
  Surface q(64, 48, 1e-6, 1e-6);
  for (std::size_t iy = 0; iy < q.ny; ++iy)
    for (std::size_t ix = 0; ix < q.nx; ++ix)
      q.at(ix, iy) = 1e-9 * (static_cast<double>(ix * ix) + 0.5 * static_cast<double>(ix * iy));
  Surface q2 = q;
  EXPECT_GT(level_surface(q, LevelingSpec::parse("plane")).rms_after, 1e-8);
  EXPECT_LT(level_surface(q2, LevelingSpec::parse("poly2")).rms_after, 1e-15);
  EXPECT_THROW(LevelingSpec::parse("poly9"), std::exception);
}

// Reference: the least-squares polynomial from the full design matrix (one row per valid sample,
// monomials evaluated with std::pow), solved by a QR decomposition of that matrix, against the
// library's separable normal equations. Holes, odd sizes, degrees 1 to 6.
TEST(Leveling, CoefficientsMatchDesignMatrixLeastSquares) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 1e-8);
  for (int degree = 1; degree <= 6; ++degree) {
    Surface s(53, 37, 1e-6, 1e-6);
    for (std::size_t iy = 0; iy < s.ny; ++iy)
      for (std::size_t ix = 0; ix < s.nx; ++ix)
        s.at(ix, iy) = 2e-6 +
                       3e-8 * std::sin(0.3 * static_cast<double>(ix)) *
                           std::cos(0.2 * static_cast<double>(iy * ix) / 40.0) +
                       noise(rng);
    for (std::size_t i = 0; i < s.size(); i += 7) s.invalidate(i);
    const Surface before = s;
    const int nt = (degree + 1) * (degree + 2) / 2;
    std::vector<std::size_t> rows;
    for (std::size_t i = 0; i < s.size(); ++i)
      if (s.valid[i]) rows.push_back(i);
    Eigen::MatrixXd a(static_cast<Eigen::Index>(rows.size()), nt);
    Eigen::VectorXd z(static_cast<Eigen::Index>(rows.size()));
    for (std::size_t r = 0; r < rows.size(); ++r) {
      const double u = (static_cast<double>(rows[r] % s.nx) - 26.0) / 26.0;
      const double v = (static_cast<double>(rows[r] / s.nx) - 18.0) / 18.0;
      int k = 0;
      for (int d = 0; d <= degree; ++d)
        for (int j = 0; j <= d; ++j)
          a(static_cast<Eigen::Index>(r), k++) = std::pow(u, d - j) * std::pow(v, j);
      z[static_cast<Eigen::Index>(r)] = before.z[rows[r]];
    }
    const Eigen::VectorXd ref = a.householderQr().solve(z);
    const LevelingResult lr = level_surface(
        s, LevelingSpec{degree == 1 ? Leveling::Plane : Leveling::Polynomial, degree});
    ASSERT_EQ(lr.coefficients.size(), static_cast<std::size_t>(nt));
    for (int k = 0; k < nt; ++k)
      EXPECT_NEAR(lr.coefficients[static_cast<std::size_t>(k)], ref[k], 1e-12)
          << "degree " << degree << " term " << k;
    const Eigen::VectorXd resid = z - a * ref;
    for (std::size_t r = 0; r < rows.size(); r += 97)
      EXPECT_NEAR(s.z[rows[r]], resid[static_cast<Eigen::Index>(r)], 1e-13) << degree;
  }
}
