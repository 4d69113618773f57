// Instrument convolution of tabulated NDFs with an angular Gaussian.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "microbrdf/error.hpp"
#include "microbrdf/generate.hpp"
#include "microbrdf/kirchhoff.hpp"
#include "microbrdf/microfacet.hpp"
#include "microbrdf/ndf_convolve.hpp"
#include "microbrdf/ndf_estimate.hpp"

using namespace microbrdf;

namespace {

constexpr double kDeg = std::numbers::pi / 180;

TabulatedNdf beckmann(std::size_t n, double alpha, double floor_rel = 0) {
  NdfSpec spec;
  spec.model = "beckmann";
  spec.alpha_x = spec.alpha_y = alpha;
  TabulatedNdf t = tabulate(*make_distribution(spec), "beckmann", n);
  // Optionally drop the far tail (keeps tests fast: empty rows are skipped).
  const double cut = floor_rel / (std::numbers::pi * alpha * alpha);
  for (double& v : t.values())
    if (v < cut) v = 0;
  t.normalise();
  return t;
}

// Integral of D(m)(m.n) over nodes strictly inside the disk.
double disk_integral(const TabulatedNdf& t) {
  double s = 0;
  for (std::size_t iy = 0; iy < t.resolution(); ++iy)
    for (std::size_t ix = 0; ix < t.resolution(); ++ix) {
      const double x = t.node_x(ix), y = t.node_y(iy);
      if (x * x + y * y < 1) s += t.at(ix, iy);
    }
  return s * t.spacing() * t.spacing();
}

// Full width at half maximum, in angle, of the profile along the line through m0 (disk
// coordinates) in direction (cos phi, sin phi); angles measured from m0 on the sphere.
double angular_fwhm(const TabulatedNdf& t, double x0, double y0, double phi) {
  const double c = std::cos(phi), s = std::sin(phi);
  const Eigen::Vector3d m0(x0, y0, std::sqrt(1 - x0 * x0 - y0 * y0));
  std::vector<double> ang, val;
  for (int k = -4000; k <= 4000; ++k) {
    const double d = k * 2e-5;
    const double x = x0 + d * c, y = y0 + d * s;
    const Eigen::Vector3d m(x, y, std::sqrt(1 - x * x - y * y));
    ang.push_back((d < 0 ? -1 : 1) * std::acos(std::clamp(m.dot(m0), -1.0, 1.0)));
    val.push_back(t.eval_disk(x, y));
  }
  const std::size_t peak =
      static_cast<std::size_t>(std::max_element(val.begin(), val.end()) - val.begin());
  const double half = 0.5 * val[peak];
  std::size_t r = peak, l = peak;
  while (r + 1 < val.size() && val[r + 1] > half) ++r;
  while (l > 0 && val[l - 1] > half) --l;
  auto cross = [&](std::size_t in, std::size_t out) {
    return ang[in] + (ang[out] - ang[in]) * (val[in] - half) / (val[in] - val[out]);
  };
  return cross(r, r + 1) - cross(l, l - 1);
}

}  // namespace

TEST(ndf_convolve, ZeroWidthIsIdentity) {
  TabulatedNdf t = beckmann(65, 0.3);
  t.meta.method = "naive";
  for (double f : {0.0, -1.0}) {
    const TabulatedNdf r = convolve_angular_gaussian(t, f);
    EXPECT_EQ(r.values(), t.values());
    EXPECT_EQ(r.meta.method, "naive");
  }
}

TEST(ndf_convolve, ConservesTheIntegral) {
  // Broad, narrow and rim-heavy tables; small and wide kernels (the wide one takes the exact
  // asin path).
  TabulatedNdf rim(129);
  for (std::size_t iy = 0; iy < 129; ++iy)
    for (std::size_t ix = 0; ix < 129; ++ix) {
      const double x = rim.node_x(ix), y = rim.node_y(iy), r2 = x * x + y * y;
      if (r2 < 1) rim.at(ix, iy) = r2 * r2;
    }
  rim.normalise();
  struct Case {
    TabulatedNdf t;
    double fwhm;
  };
  for (const Case& c :
       {Case{beckmann(257, 0.3), 1.5 * kDeg}, Case{beckmann(257, 0.3), 5 * kDeg},
        Case{beckmann(513, 0.03), 1.5 * kDeg}, Case{rim, 3 * kDeg}, Case{rim, 20 * kDeg}}) {
    const TabulatedNdf r = convolve_angular_gaussian(c.t, c.fwhm);
    std::printf("[ measured ] fwhm %.1f deg: integral change %.2e\n", c.fwhm / kDeg,
                disk_integral(r) - disk_integral(c.t));
    EXPECT_NEAR(disk_integral(r), disk_integral(c.t), 1e-6) << c.fwhm / kDeg;
    EXPECT_NEAR(r.integral(), 1.0, 1e-6);
    for (double v : r.values()) ASSERT_GE(v, 0);
  }
}

TEST(ndf_convolve, DeltaSpreadsToTheRequestedAngularWidth) {
  const std::size_t n = 1025;
  const double fwhm = 1.5 * kDeg;
  // At the centre, and at 40 deg from the normal (where disk and angle scales differ).
  for (double theta : {0.0, 40 * kDeg}) {
    TabulatedNdf t(n);
    const double x0 = std::sin(theta);
    const auto ix = static_cast<std::size_t>(std::lround((x0 + 1) / t.spacing()));
    t.at(ix, n / 2) = 1;
    t.normalise();
    const TabulatedNdf r = convolve_angular_gaussian(t, fwhm);
    const double xc = t.node_x(ix);
    const double along_x = angular_fwhm(r, xc, 0, 0);
    const double along_y = angular_fwhm(r, xc, 0, std::numbers::pi / 2);
    std::printf(
        "[ measured ] delta at %.0f deg: FWHM / requested = %.4f (radial), %.4f (azimuthal)\n",
        theta / kDeg, along_x / fwhm, along_y / fwhm);
    EXPECT_NEAR(along_x / fwhm, 1.0, 0.03) << theta / kDeg;
    EXPECT_NEAR(along_y / fwhm, 1.0, 0.03) << theta / kDeg;
    EXPECT_NEAR(disk_integral(r), 1.0, 1e-9);
  }
}

TEST(ndf_convolve, SlopeVarianceGrowsBySigmaSquared) {
  const double alpha = 0.1, fwhm = 3 * kDeg;
  const double sigma = fwhm / (2 * std::sqrt(2 * std::numbers::ln2));
  const TabulatedNdf t = beckmann(513, alpha, 1e-25);
  const TabulatedNdf r = convolve_angular_gaussian(t, fwhm);
  const Eigen::Matrix2d c0 = t.slope_covariance(), c1 = r.slope_covariance();
  EXPECT_NEAR(c0(0, 0), alpha * alpha / 2, 0.02 * alpha * alpha / 2);
  for (int a = 0; a < 2; ++a) {
    const double growth = c1(a, a) - c0(a, a);
    std::printf("[ measured ] slope variance growth / sigma^2 = %.4f (axis %d)\n",
                growth / (sigma * sigma), a);
    EXPECT_NEAR(growth / (sigma * sigma), 1.0, 0.05) << "axis " << a;
  }
  EXPECT_NEAR(c1(0, 1), 0.0, 1e-6);
  EXPECT_LT(r.at(256, 256), t.at(256, 256)) << "the peak is smeared";
}

// The instrument signature applies to every NDF method alike: on a Gaussian surface the
// 3 deg Gaussian adds its angular variance sigma^2 to the slope second moments of the naive,
// filtered and Kirchhoff tables (within 5 % per axis), and conserves their integral.
TEST(ndf_convolve, InstrumentAddsItsVarianceToEveryMethod) {
  const double fwhm = 3 * kDeg;
  const double sigma = fwhm / (2 * std::sqrt(2 * std::numbers::ln2));
  GaussianSurfaceParams gp;
  gp.nx = gp.ny = 512;  // 56 um square, 110 nm spacing (below lambda_q / 4)
  gp.sigma = 0.2e-6;    // rms height well above lambda_q / 4 pi: D_K near the geometric limit
  gp.tau_x = 6e-6;      // rms slopes sqrt(2) sigma / tau: 0.047 (x), 0.071 (y)
  gp.tau_y = 4e-6;
  const Surface s = generate_gaussian(gp);
  NdfEstimateOptions no;
  no.resolution = 513;
  no.method = NdfMethod::Naive;
  const TabulatedNdf naive = estimate_ndf(s, no);
  no.method = NdfMethod::Filtered;
  no.filter_sigma_m = 0.3e-6;
  const TabulatedNdf filtered = estimate_ndf(s, no);
  KirchhoffOptions ko;
  ko.resolution = 513;
  ko.patch_x = ko.patch_y = 0;
  const TabulatedNdf dk = estimate_kirchhoff(s, ko);
  const std::pair<const char*, const TabulatedNdf*> tables[] = {
      {"naive", &naive}, {"filtered", &filtered}, {"kirchhoff", &dk}};
  for (const auto& [name, t] : tables) {
    const TabulatedNdf r = apply_instrument(*t, fwhm);
    EXPECT_NE(r.meta.notes.find("angular Gaussian"), std::string::npos) << name;
    EXPECT_NEAR(disk_integral(r), disk_integral(*t), 1e-9) << name;
    const Eigen::Matrix2d c0 = t->slope_covariance(), c1 = r.slope_covariance();
    for (int a = 0; a < 2; ++a) {
      const double growth = c1(a, a) - c0(a, a);
      std::printf("[ measured ] %s axis %d: variance %.5g -> %.5g, added %.5g = %.4f sigma^2\n",
                  name, a, c0(a, a), c1(a, a), growth, growth / (sigma * sigma));
      EXPECT_NEAR(growth / (sigma * sigma), 1.0, 0.05) << name << " axis " << a;
    }
  }
  EXPECT_THROW(apply_instrument(naive, -fwhm), InputError);
  EXPECT_THROW(apply_instrument(naive, fwhm, &naive), InputError);
}
