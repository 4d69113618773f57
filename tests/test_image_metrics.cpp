// SSIM (Wang et al. 2004) and the RMS relative error of core/image_metrics.hpp: closed forms for
// simple images, and a brute-force reference written out from the paper's definition.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "core/image_metrics.hpp"

using namespace microbrdf::detail;

namespace {

constexpr double kC1 = 0.01 * 0.01, kC2 = 0.03 * 0.03;  // L = 1

std::vector<double> noise_image(std::size_t n, double mean, double amp, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-amp, amp);
  std::vector<double> v(n);
  for (auto& x : v) x = mean + u(rng);
  return v;
}

// Wang et al. 2004 written out plainly: for every 11 x 11 window inside the image, 2-D Gaussian
// weights (sigma 1.5) normalised to 1, centred (two-pass) weighted moments, eq. 13; the mean.
double reference_ssim(const std::vector<double>& a, const std::vector<double>& b, int w, int h) {
  double total = 0;
  int count = 0;
  for (int cy = 5; cy < h - 5; ++cy)
    for (int cx = 5; cx < w - 5; ++cx) {
      double ws = 0, ma = 0, mb = 0;
      for (int y = cy - 5; y <= cy + 5; ++y)
        for (int x = cx - 5; x <= cx + 5; ++x) {
          const double wt = std::exp(-((x - cx) * (x - cx) + (y - cy) * (y - cy)) / (2 * 2.25));
          ws += wt;
          ma += wt * a[y * w + x];
          mb += wt * b[y * w + x];
        }
      ma /= ws;
      mb /= ws;
      double va = 0, vb = 0, cov = 0;
      for (int y = cy - 5; y <= cy + 5; ++y)
        for (int x = cx - 5; x <= cx + 5; ++x) {
          const double wt =
              std::exp(-((x - cx) * (x - cx) + (y - cy) * (y - cy)) / (2 * 2.25)) / ws;
          va += wt * (a[y * w + x] - ma) * (a[y * w + x] - ma);
          vb += wt * (b[y * w + x] - mb) * (b[y * w + x] - mb);
          cov += wt * (a[y * w + x] - ma) * (b[y * w + x] - mb);
        }
      total +=
          (2 * ma * mb + kC1) * (2 * cov + kC2) / ((ma * ma + mb * mb + kC1) * (va + vb + kC2));
      ++count;
    }
  return total / count;
}

}  // namespace

TEST(Ssim, ImageWithItselfIsOne) {
  const auto a = noise_image(40 * 30, 0.5, 0.4, 1);
  EXPECT_NEAR(ssim(a, a, 40, 30), 1.0, 1e-12);
  EXPECT_NEAR(ssim(a, a, 40, 30, 255.0), 1.0, 1e-12);
  const auto small = noise_image(8 * 6, 0.5, 0.4, 2);  // smaller than the window
  EXPECT_NEAR(ssim(small, small, 8, 6), 1.0, 1e-12);
}

TEST(Ssim, ConstantImagesHaveTheLuminanceTermOnly) {
  // Flat images: variances and covariance are zero, SSIM = (2 ab + C1) / (a^2 + b^2 + C1).
  for (std::size_t n : {32u, 8u}) {
    const std::vector<double> a(n * n, 0.2), b(n * n, 0.6);
    const double expected = (2 * 0.2 * 0.6 + kC1) / (0.04 + 0.36 + kC1);
    EXPECT_NEAR(ssim(a, b, n, n), expected, 1e-9) << n;
  }
}

TEST(Ssim, InvertedCheckerboardHasNegativeStructure) {
  // 8 x 8 (one window over the whole image): means 0.5, variances 1/16, covariance -1/16.
  std::vector<double> a(64), b(64);
  for (int i = 0; i < 64; ++i) {
    a[i] = ((i % 8 + i / 8) % 2) ? 0.75 : 0.25;
    b[i] = 1 - a[i];
  }
  EXPECT_NEAR(ssim(a, b, 8, 8), (-0.125 + kC2) / (0.125 + kC2), 1e-12);
}

TEST(Ssim, MatchesTheBruteForceDefinition) {
  const int w = 37, h = 29;
  const auto a = noise_image(w * h, 0.4, 0.3, 3);
  auto b = a;
  const auto n = noise_image(w * h, 0.0, 0.1, 4);
  for (std::size_t i = 0; i < b.size(); ++i) b[i] = 0.9 * b[i] + n[i] + 0.05;
  const double s = ssim(a, b, w, h);
  EXPECT_NEAR(s, reference_ssim(a, b, w, h), 1e-12);
  EXPECT_GT(s, 0.0);
  EXPECT_LT(s, 1.0);
  EXPECT_NEAR(s, ssim(b, a, w, h), 1e-14);  // symmetric
}

TEST(Ssim, FallsAsNoiseGrows) {
  const int w = 48, h = 48;
  const auto a = noise_image(w * h, 0.5, 0.2, 5);
  double last = 1.0;
  for (double amp : {0.01, 0.05, 0.2}) {
    const auto n = noise_image(w * h, 0.0, amp, 6);
    auto b = a;
    for (std::size_t i = 0; i < b.size(); ++i) b[i] += n[i];
    const double s = ssim(a, b, w, h);
    EXPECT_LT(s, last) << amp;
    last = s;
  }
}

TEST(Ssim, RejectsMismatchedSizes) {
  const std::vector<double> a(12, 0.5), b(11, 0.5);
  EXPECT_THROW(ssim(a, b, 4, 3), std::invalid_argument);
  EXPECT_THROW(ssim(a, a, 0, 3), std::invalid_argument);
}

TEST(RmsRelative, Definition) {
  const auto b = noise_image(100, 0.5, 0.3, 7);
  auto a = b;
  for (auto& x : a) x *= 1.1;
  EXPECT_NEAR(rms_relative(a, b), 0.1, 1e-12);
  EXPECT_EQ(rms_relative(b, b), 0.0);
  const std::vector<double> zero(4, 0.0), two(4, 2.0);
  EXPECT_EQ(rms_relative(zero, zero), 0.0);
  EXPECT_NEAR(rms_relative(two, zero), 2.0, 1e-15);  // zero reference: RMS of a
}

TEST(ImageMetrics, Luminance) {
  const auto y = luminance({1.f, 1.f, 1.f, 0.f, 1.f, 0.f});
  ASSERT_EQ(y.size(), 2u);
  EXPECT_NEAR(y[0], 1.0, 1e-7);
  EXPECT_NEAR(y[1], 0.7152, 1e-7);
}
