// Sun 2002 behind the shared Brdf interface with the shared Fresnel: same values as the formula
// computed before the interface change, exact sampling pdf/weights, albedo through the sampler.
#include <array>
#include <cstdio>
#include <functional>

#include "microbrdf/brdf_albedo.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/sun2002.hpp"
#include "microbrdf/sun_brdf.hpp"
#include "microbrdf/sun_svbrdf.hpp"
#include "test_microfacet_common.hpp"

using namespace microbrdf;
using namespace microbrdf::sun2002;
using mtest::direction;

namespace {
std::shared_ptr<const Fresnel> conductor(double eta, double kappa) {
  return std::make_shared<ConductorFresnel>(constant_index(eta, kappa));
}
}  // namespace

TEST(sun2002_interface, EqualsThePreviousFormulaValues) {
  // (theta_i, phi_i, theta_o, phi_o) deg, s, n, k, as published, standard: values printed by
  // the code before the Fresnel/Brdf change (commit ef78e58: sun2002::brdf with a FresnelFn
  // holding its own Siegel-form conductor Fresnel).
  struct Ref {
    double ti, pi, to, po, s, n, k, published, standard;
  };
  const Ref refs[] = {
      {30, 180, 30, 0, 2, 0.2, 3, 0.083840069267845888, 0.096810173121335386},
      {45, 180, 20, 10, 5, 0.2, 3, 0.42392608394075704, 0.552569864865186},
      {60, 90, 50, 250, 1, 1.02, 2.577, 0.0080432153513945517, 0.015285336726009692},
      {10, 0, 70, 135, 0.5, 2.76, 3.79, 0.00068994047812738924, 0.001885673451678493},
      {80, 180, 75, 5, 10, 0.2, 3, 2.836022493339823, 14.198957565748325},
      {0, 0, 40, 0, 3, 1, 2, 0.084865262243069395, 0.11078373194319815},
  };
  for (const auto& r : refs) {
    const auto f = conductor(r.n, r.k);
    const Vec3 wi = direction(r.ti, r.pi), wo = direction(r.to, r.po);
    SunBrdf pub(r.s, BrdfForm::AsPublished, f), std_form(r.s, BrdfForm::Standard, f);
    EXPECT_NEAR(pub.eval(wi, wo, 555e-9), r.published, 1e-13 * r.published);
    EXPECT_NEAR(std_form.eval(wi, wo, 555e-9), r.standard, 1e-13 * r.standard);
    EXPECT_EQ(std_form.eval(wi, wo, 555e-9), brdf(wi, wo, r.s, BrdfForm::Standard, f.get()));
  }
  const auto f = conductor(0.2, 3.0);
  EXPECT_NEAR(albedo(0.3, 5, BrdfForm::Standard, f.get()), 0.89535706283873373, 1e-13);
  EXPECT_NEAR(albedo(0.7, 2, BrdfForm::AsPublished, f.get()), 0.23004930339083929, 1e-13);
  // A wavelength-dependent metal is evaluated at the wavelength asked for.
  const auto au = std::make_shared<ConductorFresnel>(metal("Au"));
  SunBrdf gold(3, BrdfForm::Standard, au);
  const Vec3 wi = direction(40, 180), wo = direction(40, 0);
  EXPECT_NEAR(gold.eval(wi, wo, 450e-9) / gold.eval(wi, wo, 650e-9),
              au->eval(std::cos(40 * mtest::kPi / 180), 450e-9) /
                  au->eval(std::cos(40 * mtest::kPi / 180), 650e-9),
              1e-12);
  EXPECT_THROW(SunBrdf(0.0), InputError);
}

TEST(sun2002_interface, SamplingPdfWeightsAndAlbedo) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  const auto f = conductor(0.2, 3.0);
  for (double s : {1.0, 3.0, 10.0})
    for (auto form : {BrdfForm::Standard, BrdfForm::AsPublished}) {
      SunBrdf b(s, form, f);
      for (int k = 0; k < 300; ++k) {
        const Vec3 wi = direction(85 * u(rng), 360 * u(rng));
        auto smp = b.sample(wi, u(rng), u(rng), 555e-9);
        if (!smp) continue;
        const double p = b.pdf(wi, smp->wo), fv = b.eval(wi, smp->wo, 555e-9);
        EXPECT_NEAR(smp->pdf, p, 1e-12 * p);
        EXPECT_NEAR(smp->weight, fv * smp->wo.z() / p, 1e-12 * std::max(1.0, smp->weight));
      }
      // The sampled albedo equals the quadrature of sun2002::albedo.
      for (double th : {0.0, 40.0, 70.0}) {
        const double q = albedo(th * mtest::kPi / 180, s, form, f.get());
        const double a = directional_albedo_sampled(b, direction(th, 180), 555e-9, 256);
        EXPECT_NEAR(a, q, 3e-3 * std::max(q, 0.1)) << b.describe() << " theta_i " << th;
      }
    }
  // Chi-square of the sampled directions against pdf().
  SunBrdf b(2, BrdfForm::Standard);
  const Vec3 wi = direction(50, 0);
  std::vector<Vec3> smp;
  int absorbed = 0;
  const int total = 200000;
  while (static_cast<int>(smp.size()) + absorbed < total) {
    auto r = b.sample(wi, u(rng), u(rng), 555e-9);
    if (r)
      smp.push_back(r->wo);
    else
      ++absorbed;
  }
  const double kept = static_cast<double>(smp.size()) / total;
  auto r = mtest::chi_square(mtest::Chart(Eigen::Matrix3d::Identity()), smp,
                             [&](const Vec3& wo) { return b.pdf(wi, wo) / kept; });
  EXPECT_LT(r.chi2, r.critical);
  EXPECT_NEAR(r.total_expected, 1.0, 5e-3);
  std::printf("Sun s = 2, theta_i 50: chi2/dof %.3f (dof %d), kept %.4f\n", r.chi2 / r.dof, r.dof,
              kept);
}

TEST(sun2002_interface, FreeTravelProbabilityTermsOfFig8) {
  // Sun's Fig. 8 rows: without the free travel probabilities, with the viewer's only, with both.
  // Each left-out term is exactly a factor Gamma_0 of the light (wi) or viewer (wo) direction.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  const auto f = conductor(0.27, 3.4);
  for (double s : {1.0, 3.0, 20.0})
    for (auto form : {BrdfForm::Standard, BrdfForm::AsPublished}) {
      const SunBrdf both(s, form, f), none(s, form, f, FtpTerms::None),
          view(s, form, f, FtpTerms::ViewOnly), light(s, form, f, FtpTerms::LightOnly);
      for (int k = 0; k < 200; ++k) {
        const double ti = 88 * u(rng), to = 88 * u(rng);
        const Vec3 wi = direction(ti, 360 * u(rng)), wo = direction(to, 360 * u(rng));
        const double gi = ftp(ti * mtest::kPi / 180, s), go = ftp(to * mtest::kPi / 180, s);
        const double fb = both.eval(wi, wo, 600e-9);
        if (!(fb > 1e-250)) continue;
        EXPECT_NEAR(none.eval(wi, wo, 600e-9), fb / (gi * go), 1e-10 * fb / (gi * go));
        EXPECT_NEAR(view.eval(wi, wo, 600e-9), fb / gi, 1e-10 * fb / gi);
        EXPECT_NEAR(light.eval(wi, wo, 600e-9), fb / go, 1e-10 * fb / go);
        // Leaving out one term breaks reciprocity exactly by the ratio of the two terms.
        EXPECT_NEAR(view.eval(wo, wi, 600e-9), fb / go, 1e-10 * fb / go);
        // Sampling stays consistent (weight = f cos / pdf with the same pdf).
        const auto smp = none.sample(wi, u(rng), u(rng), 600e-9);
        if (smp) {
          EXPECT_NEAR(smp->pdf, both.pdf(wi, smp->wo), 1e-12 * smp->pdf);
          const double fv = none.eval(wi, smp->wo, 600e-9);
          EXPECT_NEAR(smp->weight, fv * smp->wo.z() / smp->pdf, 1e-12 * std::max(1.0, smp->weight));
        }
      }
    }
  // Names as the command line takes them.
  EXPECT_EQ(parse_ftp_terms("view"), FtpTerms::ViewOnly);
  EXPECT_EQ(ftp_terms_name(FtpTerms::None), "none");
  EXPECT_EQ(parse_brdf_form("published"), BrdfForm::AsPublished);
  EXPECT_THROW(parse_ftp_terms("viewer"), InputError);
  EXPECT_THROW(parse_brdf_form("printed"), InputError);
  // The energy bound of the paper holds only with both terms: without them a rough surface
  // reflects more than the incident energy at grazing incidence (albedo through the sampler).
  const SunBrdf rough_none(1, BrdfForm::Standard, nullptr, FtpTerms::None),
      rough_both(1, BrdfForm::Standard);
  const double a_none = directional_albedo_sampled(rough_none, direction(80, 0), 555e-9, 256);
  const double a_both = directional_albedo_sampled(rough_both, direction(80, 0), 555e-9, 256);
  std::printf("s = 1, theta_i 80, R = 1: albedo without FTP %.3f, with both %.3f\n", a_none,
              a_both);
  EXPECT_LT(a_both, 1.0);
  EXPECT_GT(a_none, 3 * a_both);
}

namespace {
TextureImage image(int w, int h, const std::function<std::array<float, 3>(int, int)>& px) {
  TextureImage t;
  t.width = w;
  t.height = h;
  t.path = "test.png";
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (float c : px(x, y)) t.rgb.push_back(c);
  return t;
}
}  // namespace

TEST(sun2002_interface, SmoothnessAndColourTextures) {
  // Sun's Fig. 11: s and the colour per texel. A 4 x 2 smoothness map (grey x/3 in row 0, the
  // top; 1 - x/3 in row 1) with s from 2 to 20; v runs up the rows, u along the columns.
  SunTextureOptions o;
  o.s_map = image(4, 2, [](int x, int y) {
    const float g = y == 0 ? float(x) / 3 : 1 - float(x) / 3;
    return std::array<float, 3>{g, g, g};
  });
  o.s_min = 2;
  o.s_max = 20;
  o.form = BrdfForm::AsPublished;
  o.fresnel = conductor(0.27, 3.4);
  const SunTextureSvbrdf t(o);
  auto s_at = [](int x, int y) { return 2 + 18 * (y == 0 ? x / 3.0 : 1 - x / 3.0); };
  // (u, v) = (0.1, 0.25): column 0, bottom row (row 1): g = 1, s = 20; (0.9, 0.75): column 3,
  // top row: g = 1, s = 20; (0.3, 0.75): column 1, top: s = 8. Wrapping: u + 3, v - 2.
  EXPECT_NEAR(t.smoothness(0.1, 0.25), 20, 1e-5);
  EXPECT_NEAR(t.smoothness(0.9, 0.75), 20, 1e-5);
  EXPECT_NEAR(t.smoothness(0.3, 0.75), 8, 1e-5);
  EXPECT_NEAR(t.smoothness(3.3, -1.25), 8, 1e-5);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (int k = 0; k < 200; ++k) {
    const int x = k % 4, y = (k / 4) % 2;
    const double uu = (x + 0.5) / 4, vv = (y == 0 ? 0.75 : 0.25);
    const double s = t.smoothness(uu, vv);
    EXPECT_NEAR(s, s_at(x, y), 1e-5);
    const SunBrdf ref(s, BrdfForm::AsPublished, o.fresnel);
    const Vec3 wi = direction(80 * u(rng), 360 * u(rng)), wo = direction(80 * u(rng), 360 * u(rng));
    const double fr = ref.eval(wi, wo, 500e-9);
    EXPECT_NEAR(t.eval(uu, vv, wi, wo, 500e-9), fr, 1e-12 * fr + 1e-300);
    EXPECT_NEAR(t.pdf(uu, vv, wi, wo), ref.pdf(wi, wo), 1e-12 * ref.pdf(wi, wo) + 1e-300);
    const auto a = t.sample(uu, vv, wi, 0.3, 0.6, 500e-9);
    const auto b = ref.sample(wi, 0.3, 0.6, 500e-9);
    ASSERT_EQ(bool(a), bool(b));
    if (a) {
      EXPECT_NEAR((a->wo - b->wo).norm(), 0, 1e-12);
      EXPECT_NEAR(a->weight, b->weight, 1e-12 * std::max(1.0, b->weight));
    }
  }
  // Colour texels: each becomes the metal that `--color` makes of that colour (eta = 1, kappa
  // from the colour's smooth reflectance spectrum): same normal-incidence reflectance (kappa
  // tabulated on the 5 nm grid of the colour fit), and the Fresnel term at other angles.
  SunTextureOptions c;
  c.s = 6;
  const std::array<std::array<float, 3>, 3> colours = {
      {{230 / 255.f, 194 / 255.f, 122 / 255.f}, {0.8f, 0.2f, 0.2f}, {1.f, 1.f, 1.f}}};
  c.color_map = image(3, 1, [&](int x, int) { return colours[std::size_t(x)]; });
  const SunTextureSvbrdf ct(c);
  EXPECT_EQ(ct.distinct_colours(), 3u);
  for (int x = 0; x < 2; ++x) {
    const auto& col = colours[std::size_t(x)];
    const auto oc = from_srgb(std::round(col[0] * 255) / 255, std::round(col[1] * 255) / 255,
                              std::round(col[2] * 255) / 255);
    const ConductorFresnel ref(oc);
    for (double nm : {405.0, 450.0, 532.0, 610.0, 700.0}) {
      EXPECT_NEAR(ct.normal_reflectance_at((x + 0.5) / 3, 0.5, nm * 1e-9), ref.eval(1.0, nm * 1e-9),
                  1e-5)
          << x << " " << nm;
      const Vec3 wi = direction(60, 0), wo = direction(30, 180);
      const double fr = sun2002::brdf(wi, wo, 6, BrdfForm::Standard, &ref, nm * 1e-9);
      EXPECT_NEAR(ct.eval((x + 0.5) / 3, 0.5, wi, wo, nm * 1e-9), fr, 1e-5 * fr);
    }
  }
  // White is clamped to a reflectance below 1 (linear 0.98), not rejected.
  EXPECT_GT(ct.normal_reflectance_at(2.5 / 3, 0.5, 550e-9), 0.95);
  EXPECT_LT(ct.normal_reflectance_at(2.5 / 3, 0.5, 550e-9), 1.0);
  // Bad ranges are refused.
  SunTextureOptions bad = o;
  bad.s_min = 0;
  EXPECT_THROW(SunTextureSvbrdf{bad}, InputError);
  bad.s_min = 30;
  EXPECT_THROW(SunTextureSvbrdf{bad}, InputError);
}
