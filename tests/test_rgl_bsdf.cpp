// RGL .bsdf export and reconstruction: microbrdf's writer, its reader (RglBrdf) and an
// independent reader (tests/rgl_reference_reader.py) against the BRDF that was exported.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>

#include "microbrdf/brdf_albedo.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/export.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/io.hpp"
#include "microbrdf/level.hpp"
#include "microbrdf/measured.hpp"
#include "microbrdf/measured_ndf.hpp"
#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/ndf_estimate.hpp"
#include "microbrdf/rgl_bsdf.hpp"
#include "microbrdf/tabulated_distribution.hpp"
#include "test_microfacet_common.hpp"

using namespace microbrdf;

namespace {
Vec3 dir(double theta_deg, double phi_deg) { return mtest::direction(theta_deg, phi_deg); }

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
// `ref` must be const-usable for sampling too.
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
      // Half the directions uniform over the hemisphere, half drawn from the BRDF's own sampler
      // (narrow lobes are missed by uniform directions).
      Vec3 wo = dir(89 * std::sqrt(u(rng)), 360 * u(rng));
      const double u1 = u(rng), u2 = u(rng);
      if (k % 2 == 1)
        if (auto s = ref.sample(wi, u1, u2, 550e-9)) wo = s->wo;
      const double v = ref.eval(wi, wo, 550e-9) * wo.z();
      pts.push_back({wo, v});
      vmax = std::max(vmax, v);
    }
    for (const auto& [wo, v] : pts)
      if (v > 0 && v >= 0.01 * vmax) errs.push_back(std::abs(got(wi, wo) * wo.z() - v) / v);
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

namespace {

const std::string kReader = std::string(MICROBRDF_TEST_DATA) + "/../rgl_reference_reader.py";

std::string scratch(const std::string& name) {
  return ::testing::TempDir() + "microbrdf_rgl_" + std::to_string(::getpid()) + "_" + name;
}

std::string run(const std::string& cmd) {
  std::string out;
  FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) return out;
  char buf[256];
  while (std::fgets(buf, sizeof buf, p)) out += buf;
  EXPECT_EQ(::pclose(p), 0) << cmd;
  return out;
}

// Writes the .bsdf, has the independent reader evaluate it at the same (wi, wo) pairs as
// median_relative_error draws, and compares its sampled albedo with quadrature.
void check_with_independent_reader(const Brdf& brdf, const MicrofacetDistribution& d,
                                   const RglExportOptions& o, const std::string& tag,
                                   double median_tol, double albedo_tol) {
  const std::string file = scratch(tag + ".bsdf"), queries = scratch(tag + ".q"),
                    answers = scratch(tag + ".a");
  write_rgl_bsdf(brdf, d, o, file);
  // First pass: collect the pairs; second: read the reader's answers back in the same order.
  std::vector<std::array<double, 6>> pairs;
  median_relative_error(
      brdf,
      [&](const Vec3& wi, const Vec3& wo) {
        pairs.push_back({wi.x(), wi.y(), wi.z(), wo.x(), wo.y(), wo.z()});
        return 0.0;
      },
      o.isotropic, 7);
  {
    std::ofstream q(queries);
    q.precision(17);
    for (const auto& p : pairs)
      q << p[0] << ' ' << p[1] << ' ' << p[2] << ' ' << p[3] << ' ' << p[4] << ' ' << p[5]
        << " 550\n";
  }
  run("/usr/bin/python3 " + kReader + " " + file + " eval " + queries + " " + answers);
  std::ifstream a(answers);
  std::vector<double> got;
  for (double v; a >> v;) got.push_back(v);
  ASSERT_EQ(got.size(), pairs.size());
  std::size_t k = 0;
  const double med = median_relative_error(
      brdf, [&](const Vec3&, const Vec3&) { return got[k++]; }, o.isotropic, 7);
  std::printf("[ %s ] independent reader: median relative error %.4f over %zu lobe pairs\n",
              tag.c_str(), med, pairs.size());
  EXPECT_LT(med, median_tol) << tag;
  for (double ti : {0.0, 30.0, 60.0}) {
    const double phi = o.isotropic ? 0.0 : 35.0;
    const double ref = directional_albedo_sampled(brdf, dir(ti, phi), 550e-9, 512);
    const double sampled =
        std::stod(run("/usr/bin/python3 " + kReader + " " + file + " albedo " + std::to_string(ti) +
                      " " + std::to_string(phi) + " 550 128"));
    std::printf(
        "[ %s ] theta_i %2.0f: albedo (own sampler, 512^2) %.4f, independent reader sampled %.4f "
        "(%+.2f%%)\n",
        tag.c_str(), ti, ref, sampled, 100 * (sampled / ref - 1));
    EXPECT_NEAR(sampled, ref, albedo_tol * ref) << tag << " theta_i " << ti;
  }
  if (!::testing::Test::HasFailure()) {
    std::remove(file.c_str());
    std::remove(queries.c_str());
    std::remove(answers.c_str());
  }
}

}  // namespace

TEST(RglBsdf, IndependentReaderIsotropicGgx) {
  const auto c = ggx(0.3, 0.3);
  check_with_independent_reader(*c.brdf, *c.d, RglExportOptions{}, "iso_ggx", 0.02, 0.02);
}

TEST(RglBsdf, IndependentReaderAnisotropicGgx) {
  const auto c = ggx(0.1, 0.3, 0.4);
  RglExportOptions o;
  o.isotropic = false;
  o.theta_i = 12;
  o.wavelengths_nm = {500, 550, 600};
  check_with_independent_reader(*c.brdf, *c.d, o, "aniso_ggx", 0.02, 0.02);
}

TEST(RglBsdf, IndependentReaderFilteredNdfOfARealScan) {
  // The Zygo MetroPro scan in tests/data (640 x 480, 1.1 um spacing), plane levelled, filtered
  // NDF with a 2 um Gaussian; the BRDF is the microfacet BRDF of that table (iron).
  Surface s = read_surface(std::string(MICROBRDF_TEST_DATA) + "/metropro-1.dat");
  level_surface(s, LevelingSpec{});
  NdfEstimateOptions eo;
  eo.resolution = 513;
  eo.filter_sigma_m = 2e-6;
  auto d = std::make_shared<TabulatedDistribution>(estimate_ndf(s, eo));
  const MicrofacetBrdf brdf(d, std::make_shared<ConductorFresnel>(metal("Fe")));
  RglExportOptions o;
  o.isotropic = false;
  o.theta_i = 12;
  o.wavelengths_nm = {500, 550, 600};
  check_with_independent_reader(brdf, *d, o, "scan_filtered", 0.02, 0.02);
}

TEST(RglBsdf, MerlToBsdfKeepsTheMeasuredBrdf) {
  // MERL table of a GGX conductor -> .bsdf parameterised by the table's own lobe (eq. 9 shape).
  const auto c = ggx(0.2, 0.2);
  const MerlBrdf merl(parse_merl(encode_merl(tabulate_merl(*c.brdf)), "ggx.binary"));
  const auto lobe = lobe_distribution(merl, 257);
  RglExportOptions o;
  o.wavelengths_nm = {532};
  const RglBrdf r(rgl_tensor(merl, *lobe, o), "merl.bsdf");
  const double med = median_relative_error(
      merl, [&](const Vec3& wi, const Vec3& wo) { return r.eval(wi, wo, 532e-9); }, true, 3);
  std::printf("[ MERL -> .bsdf ] median relative error against the MERL table %.4f\n", med);
  EXPECT_LT(med, 0.02);
}

TEST(RglBsdf, IsotropyProbeAndExportDistribution) {
  EXPECT_TRUE(brdf_is_isotropic(*ggx(0.3, 0.3).brdf));
  EXPECT_TRUE(brdf_is_isotropic(*ggx(0.3, 0.3, 0.7).brdf));  // phi of a round lobe is moot
  EXPECT_FALSE(brdf_is_isotropic(*ggx(0.1, 0.3).brdf));
  EXPECT_FALSE(brdf_is_isotropic(*ggx(0.3, 0.31, 0.4).brdf));  // 3 % anisotropy is seen
  EXPECT_FALSE(brdf_is_isotropic(*ggx(0.01, 0.02).brdf));      // narrow lobes are probed
  const MerlBrdf merl(MerlTable{});
  EXPECT_TRUE(brdf_is_isotropic(merl));
  // A microfacet BRDF is parameterised by its own NDF; anything else by its lobe.
  const auto c = ggx(0.2, 0.2);
  const auto d = export_distribution(c.brdf);
  EXPECT_EQ(d.get(), c.d.get());
  const auto m = std::make_shared<MerlBrdf>(tabulate_merl(*c.brdf));
  const auto lobe = export_distribution(m);
  EXPECT_NE(dynamic_cast<const TabulatedDistribution*>(lobe.get()), nullptr);
  EXPECT_NEAR(lobe->D(Vec3(0, 0, 1)) / c.d->D(Vec3(0, 0, 1)), 1.0, 0.05);
}
