// Sun 2002 behind the shared Brdf interface with the shared Fresnel: same values as the formula
// computed before the interface change, exact sampling pdf/weights, albedo through the sampler.
#include <cstdio>

#include "microbrdf/brdf_albedo.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/sun2002.hpp"
#include "microbrdf/sun_brdf.hpp"
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
