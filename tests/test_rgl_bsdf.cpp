// RGL .bsdf export and reconstruction: microbrdf's writer, its reader (RglBrdf) and an
// independent reader (tests/rgl_reference_reader.py) against the BRDF that was exported.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>

#include "microbrdf/error.hpp"
#include "microbrdf/export.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/rgl_bsdf.hpp"

using namespace microbrdf;

namespace {
constexpr double kDeg = 3.14159265358979323846 / 180.0;
Vec3 dir(double theta_deg, double phi_deg) {
  const double t = theta_deg * kDeg, p = phi_deg * kDeg;
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

struct Case {
  std::shared_ptr<MicrofacetDistribution> d;
  std::shared_ptr<MicrofacetBrdf> brdf;
};
Case ggx(double ax, double ay, double phi = 0) {
  Case c;
  c.d = std::make_shared<GgxDistribution>(ax, ay, phi);
  c.brdf = std::make_shared<MicrofacetBrdf>(
      c.d, std::make_shared<ConductorFresnel>(constant_index(1.2, 3.5)));
  return c;
}

// Median relative error of `got` against `ref` over (wi, wo) pairs where f cos(theta_o) is at
// least 1% of the largest value seen for that wi (where the lobe matters).
template <class F>
double median_relative_error(const Brdf& ref, F got, bool isotropic, int seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> errs;
  for (double ti : {0.0, 15.0, 30.0, 45.0, 60.0, 75.0}) {
    const Vec3 wi = dir(ti, isotropic ? 0.0 : 360 * u(rng));
    std::vector<std::pair<Vec3, double>> pts;
    double vmax = 0;
    for (int k = 0; k < 400; ++k) {
      const Vec3 wo = dir(89 * std::sqrt(u(rng)), 360 * u(rng));
      const double v = ref.eval(wi, wo, 550e-9) * wo.z();
      pts.push_back({wo, v});
      vmax = std::max(vmax, v);
    }
    for (const auto& [wo, v] : pts)
      if (v >= 0.01 * vmax) errs.push_back(std::abs(got(wi, wo) * wo.z() - v) / v);
  }
  std::nth_element(errs.begin(), errs.begin() + errs.size() / 2, errs.end());
  return errs[errs.size() / 2];
}
}  // namespace

TEST(RglBsdf, OwnReaderReproducesIsotropicGgx) {
  const auto c = ggx(0.3, 0.3);
  RglExportOptions o;
  const auto file = rgl_tensor(*c.brdf, *c.d, o);
  const RglBrdf r(parse_tensor_file(encode_tensor_file(file), "mem.bsdf"), "mem.bsdf");
  EXPECT_TRUE(r.isotropic());
  const double med = median_relative_error(
      *c.brdf, [&](const Vec3& wi, const Vec3& wo) { return r.eval(wi, wo, 550e-9); }, true, 1);
  EXPECT_LT(med, 0.02);
  // Sampling: the pdf of sample() is pdf(), and the sampled albedo matches quadrature.
  for (double ti : {0.0, 40.0, 70.0}) {
    const Vec3 wi = dir(ti, 0);
    const double a_ref = directional_albedo(*c.brdf, wi, 550e-9);
    const double a = directional_albedo_sampled(r, wi, 550e-9, 256);
    EXPECT_NEAR(a, a_ref, 0.02 * a_ref) << "theta_i " << ti;
    const auto s = r.sample(wi, 0.3, 0.7, 550e-9);
    ASSERT_TRUE(s);
    EXPECT_NEAR(r.pdf(wi, s->wo), s->pdf, 1e-3 * s->pdf);
  }
}

TEST(RglBsdf, OwnReaderReproducesAnisotropicGgx) {
  const auto c = ggx(0.1, 0.3, 0.4);
  RglExportOptions o;
  o.isotropic = false;
  o.theta_i = 12;
  o.phi_i = 17;
  o.wavelengths_nm = {500, 550, 600};
  const auto file = rgl_tensor(*c.brdf, *c.d, o);
  const RglBrdf r(file, "mem.bsdf");
  EXPECT_FALSE(r.isotropic());
  const double med = median_relative_error(
      *c.brdf, [&](const Vec3& wi, const Vec3& wo) { return r.eval(wi, wo, 550e-9); }, false, 2);
  EXPECT_LT(med, 0.02);
}

TEST(RglBsdf, MalformedTablesAreRejected) {
  const auto c = ggx(0.3, 0.3);
  RglExportOptions o;
  o.theta_i = 4;
  o.samples = 4;
  o.ndf_theta = o.ndf_phi = 8;
  auto file = rgl_tensor(*c.brdf, *c.d, o);
  auto bad = file;
  for (auto& f : bad.fields)
    if (f.name == "vndf") std::fill(f.data.begin(), f.data.end(), 0);
  EXPECT_THROW(RglBrdf(bad, "bad.bsdf"), FileError);
  bad = file;
  for (auto& f : bad.fields)
    if (f.name == "spectra") f.shape[2] = 7;
  EXPECT_THROW(RglBrdf(bad, "bad.bsdf"), FileError);
  bad = file;
  bad.fields.erase(bad.fields.begin() + 2);
  EXPECT_THROW(RglBrdf(bad, "bad.bsdf"), FileError);
}
