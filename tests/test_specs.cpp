// The one material and BRDF vocabulary (material_spec.hpp, brdf_spec.hpp), the slice convention
// (brdf_slice.hpp) and the experiments that live in the library: Sun's k_tau fit and agreement
// metrics, the SH diagnostics, the chunked SH estimate and the goniometer's cone average.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "microbrdf/brdf.hpp"
#include "microbrdf/brdf_slice.hpp"
#include "microbrdf/brdf_spec.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/goniometer.hpp"
#include "microbrdf/lambertian_brdf.hpp"
#include "microbrdf/material_spec.hpp"
#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/sh_basis.hpp"
#include "microbrdf/sh_brdf.hpp"
#include "microbrdf/sun2002.hpp"

using namespace microbrdf;
using nlohmann::json;

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kLambda = 555e-9;

// The message of the InputError `f` throws ("" when it throws nothing).
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(MaterialSpec, EachFormGivesItsReflectance) {
  // A metal: the table's Fresnel term.
  const auto cu = make_fresnel(parse_material({{"metal", "Cu"}}));
  EXPECT_DOUBLE_EQ(cu->eval(1.0, kLambda), ConductorFresnel(metal("Cu")).eval(1.0, kLambda));
  // n, k as numbers or as typed strings: R0 = ((n-1)^2 + k^2) / ((n+1)^2 + k^2).
  const double r0 = ((0.2 - 1) * (0.2 - 1) + 9) / ((0.2 + 1) * (0.2 + 1) + 9);
  EXPECT_NEAR(make_fresnel(parse_material({{"n", 0.2}, {"k", 3.0}}))->eval(1.0, kLambda), r0,
              1e-12);
  EXPECT_NEAR(make_fresnel(parse_material({{"n", "0.2"}, {"k", "3"}}))->eval(1.0, kLambda), r0,
              1e-12);
  // R0: exact Fresnel with eta = 1 and Schlick agree at normal incidence, differ at 70 deg.
  const auto exact = make_fresnel(parse_material({{"r0", 0.6}}));
  const auto schlick = make_fresnel(parse_material({{"r0", "0.6"}, {"fresnel", "schlick"}}));
  EXPECT_NEAR(exact->eval(1.0, kLambda), 0.6, 1e-9);
  EXPECT_NEAR(schlick->eval(1.0, kLambda), 0.6, 1e-9);
  EXPECT_NEAR(schlick->eval(std::cos(70 * kPi / 180), kLambda),
              fresnel_schlick(std::cos(70 * kPi / 180), 0.6), 1e-9);
  // A CSV file of optical constants.
  const std::string csv =
      std::string(MICROBRDF_TEST_DATA) + "/../../data/optical/Au_JohnsonChristy1972.csv";
  EXPECT_NEAR(make_fresnel(parse_material({{"nk_csv", csv}}))->eval(1.0, kLambda),
              ConductorFresnel(metal("Au")).eval(1.0, kLambda), 1e-9);
  // A colour: "#rrggbb" and "r,g,b" in 0..255 and 0..1 are the same colour.
  const double a = make_fresnel(parse_material({{"color", "#e6c27a"}}))->eval(1.0, kLambda);
  const double b = make_fresnel(parse_material({{"color", "230,194,122"}}))->eval(1.0, kLambda);
  const double c =
      make_fresnel(parse_material({{"color", "0.90196,0.76078,0.47843"}}))->eval(1.0, kLambda);
  EXPECT_NEAR(a, b, 1e-12);
  EXPECT_NEAR(a, c, 1e-4);
  EXPECT_GT(a, 0.3);
  EXPECT_LT(a, 1.0);
}

TEST(MaterialSpec, RoundTripAndFallback) {
  for (const json& j :
       {json{{"metal", "Al"}, {"fresnel", "exact"}},
        json{{"n", 1.5}, {"k", 2.0}, {"fresnel", "schlick"}},
        json{{"r0", 0.25}, {"fresnel", "exact"}}, json{{"color", "#102030"}, {"fresnel", "exact"}}})
    EXPECT_EQ(parse_material(j).to_json(), j);
  EXPECT_EQ(parse_material(json::object(), MaterialSpec::named_metal("Fe")).metal, "Fe");
  EXPECT_NE(error_of([] { parse_material(json::object()); }).find("give a material"),
            std::string::npos);
}

TEST(MaterialSpec, ErrorsNameTheKeysInTheCallersStyle) {
  const std::string two = error_of([] {
    parse_material({{"metal", "Au"}, {"r0", "0.5"}}, {}, KeyStyle::Cli);
  });
  EXPECT_NE(two.find("--metal"), std::string::npos) << two;
  EXPECT_NE(two.find("--r0"), std::string::npos) << two;
  const std::string lone = error_of([] { parse_material({{"n", 1.2}}, {}, KeyStyle::Python); });
  EXPECT_NE(lone.find("k="), std::string::npos) << lone;
  EXPECT_NE(error_of([] { parse_material({{"nk_csv", "x"}, {"color", "1,2"}}); }), "");
  EXPECT_NE(error_of([] {
              parse_material({{"color", "1,2"}});
            }).find("\"color\""),
            std::string::npos);
  EXPECT_NE(error_of([] { parse_material({{"r0", 1.0}}); }), "");
  EXPECT_NE(error_of([] { parse_material({{"metal", "Unobtainium"}}); }), "");
  EXPECT_NE(error_of([] { parse_material({{"metal", "Au"}, {"fresnel", "Al"}}); }), "");
  EXPECT_NE(error_of([] { parse_material({{"n", "1.2x"}, {"k", 1}}); }), "");
}

TEST(BrdfSpec, AnalyticModelFromEitherSpelling) {
  const BrdfSpec a = parse_brdf({{"model", "ellipsoid"},
                                 {"alpha_x", 0.1},
                                 {"alpha_y", "0.3"},
                                 {"theta_x", "5deg"},
                                 {"theta_z", 20}});
  EXPECT_EQ(a.kind, BrdfSpec::Kind::Analytic);
  EXPECT_DOUBLE_EQ(a.model.alpha_x, 0.1);
  EXPECT_DOUBLE_EQ(a.model.alpha_y, 0.3);
  EXPECT_NEAR(a.model.theta_x, 5 * kPi / 180, 1e-15);   // a unit given
  EXPECT_NEAR(a.model.theta_z, 20 * kPi / 180, 1e-15);  // a bare number is degrees
  const BrdfSpec iso = parse_brdf({{"alpha", "0.2"}});
  EXPECT_EQ(iso.model.model, "ggx");
  EXPECT_DOUBLE_EQ(iso.model.alpha_y, 0.2);
  // make_brdf builds the same BRDF as the classes do by hand.
  const auto f = make_fresnel(MaterialSpec::named_metal("Cu"));
  const MicrofacetBrdf hand(make_distribution(iso.model), f);
  const auto built = make_brdf(iso, MaterialSpec::named_metal("Cu"));
  const Vec3 wi = slice_light(0.5), wo = slice_view(0.5, 0.3, SlicePlane::In);
  EXPECT_DOUBLE_EQ(built->eval(wi, wo, kLambda), hand.eval(wi, wo, kLambda));
}

TEST(BrdfSpec, KindsAndTheirKeys) {
  EXPECT_EQ(parse_brdf({{"lambertian", "0.5"}}).kind, BrdfSpec::Kind::Lambertian);
  EXPECT_EQ(parse_brdf({{"mirror", true}}).kind, BrdfSpec::Kind::Mirror);
  EXPECT_EQ(parse_brdf({{"sun", 2}}).kind, BrdfSpec::Kind::Sun);
  const BrdfSpec k = parse_brdf({{"kirchhoff", json::array({"a.npy", "b.npy"})}, {"alpha", 0.2}});
  EXPECT_EQ(k.kind, BrdfSpec::Kind::Kirchhoff);
  EXPECT_TRUE(k.model_given);  // the model supplies the shadowing
  EXPECT_EQ(k.kirchhoff.size(), 2u);
  const BrdfSpec sh = parse_brdf({{"sh", "x.shbrdf"}, {"l_filter", 8}, {"filter_width", "2"}});
  EXPECT_EQ(sh.sh_l_filter, 8);
  EXPECT_FALSE(sh.uses_material());
  EXPECT_NE(error_of([] {
              parse_brdf({{"ndf", "x.npy"}, {"alpha", 0.1}});
            }).find("replaces"),
            std::string::npos);
  EXPECT_NE(error_of([] {
              parse_brdf({{"sun", 2}, {"lambertian", 1}});
            }).find("one BRDF"),
            std::string::npos);
  EXPECT_NE(error_of([] { parse_brdf({{"alpha", 0.1}, {"l_filter", 3}}); }), "");
  EXPECT_NE(error_of([] { parse_brdf({{"lambertian", 1.5}}); }), "");
  EXPECT_NE(error_of([] { parse_brdf({{"model", "ggx"}}); }).find("roughness"), std::string::npos);
  EXPECT_NE(error_of([] { parse_brdf({{"alpha", 0.1}, {"phi", "ten"}}); }), "");
  // A Lambertian spec is the Lambertian BRDF.
  const auto l = make_brdf(parse_brdf({{"lambertian", 0.5}}), MaterialSpec{});
  EXPECT_NEAR(l->eval(Vec3(0, 0, 1), Vec3(0.6, 0, 0.8), kLambda), 0.5 / kPi, 1e-15);
  EXPECT_TRUE(l->lobes().diffuse);
}

TEST(SliceConvention, MirrorDirectionAtPlusThetaI) {
  for (double ti : {0.0, 0.3, 1.2}) {
    const Vec3 wi = slice_light(ti);
    EXPECT_LT(wi.x(), 1e-15);  // the light at azimuth 180 deg
    const Vec3 mirror(-wi.x(), -wi.y(), wi.z());
    EXPECT_LT((slice_view(ti, ti, SlicePlane::In) - mirror).norm(), 1e-15);
    EXPECT_LT((slice_view(ti, 0, SlicePlane::Out) - mirror).norm(), 1e-15);
    // The out-of-plane cut leaves the plane of incidence at right angles.
    EXPECT_NEAR(slice_view(ti, kPi / 2 - 1e-9, SlicePlane::Out).y(), 1, 1e-12);
  }
  EXPECT_EQ(parse_slice_plane("out"), SlicePlane::Out);
  EXPECT_THROW(parse_slice_plane("up"), InputError);
}

TEST(SunExperiments, FitKTauRecoversTheConstant) {
  std::vector<double> th, g;
  for (int i = 1; i < 90; i += 2) {
    th.push_back(i * kPi / 180);
    g.push_back(sun2002::ftp(th.back(), 0.5, 2.5));
  }
  EXPECT_NEAR(sun2002::fit_k_tau(0.5, th, g), 2.5, 1e-6);
  EXPECT_TRUE(std::isnan(sun2002::fit_k_tau(0.5, {}, {})));
}

TEST(SunExperiments, AgreementMetricsOfAKnownCurve) {
  // A "simulation" equal to Sun's curve with k_tau = 2 plus a bump at 40 deg in the any-crossing
  // count: the metrics find the bump, the fit finds k_tau.
  sun2002::FtpSimResult r;
  r.params.s = 1;
  for (int d = 0; d <= 90; d += 5) {
    sun2002::FtpSimPoint p;
    p.theta = d * kPi / 180;
    p.gamma_leaving = sun2002::ftp(p.theta, 1, 2.0);
    p.gamma_any = sun2002::ftp(p.theta, 1) + (d == 40 ? -0.05 : 0.0);
    p.se_leaving = d == 10 ? 0.01 : 0.001;
    p.rays = 100;
    r.points.push_back(p);
  }
  const auto a = sun2002::compare_ftp(r);
  EXPECT_NEAR(a.best_k_tau_leaving, 2.0, 1e-6);
  EXPECT_NEAR(a.any_minus_sun.diff, -0.05, 1e-12);
  EXPECT_NEAR(a.any_minus_sun.theta, 40 * kPi / 180, 1e-12);
  EXPECT_LT(a.leaving_minus_sun.diff, 0);  // k_tau = 2 blocks more than k_tau = 1
  EXPECT_DOUBLE_EQ(a.max_standard_error_leaving, 0.01);
  EXPECT_EQ(a.rays, 1900u);
}

TEST(ShDiagnostics, LambertianProjection) {
  // rho = 1/pi: every directional albedo is 1, and so is the hemispherical albedo; the odd
  // expansion of cos(theta_i) cos(theta_o) / pi is exact at l = 1 and never negative.
  const ShBrdf b = ShBrdf::project(LambertianBrdf(1.0), 5, kLambda);
  for (const auto& p : sh_albedo_table(b)) EXPECT_NEAR(p.albedo, 1.0, 1e-9) << p.theta_i_deg;
  EXPECT_NEAR(sh_hemispherical_albedo(b), 1.0, 1e-9);
  const ShRinging r = sh_ringing(b);
  EXPECT_EQ(r.negative_fraction, 0.0);
  EXPECT_GT(r.min_cosine_weighted, 0.0);
  EXPECT_LE(r.max_cosine_weighted, 1 / kPi + 1e-9);
}

TEST(ShDiagnostics, ChunkedEstimateDependsOnTheSeedOnly) {
  const LambertianBrdf l(0.7);
  omp_set_num_threads(1);
  const ShEstimator one = sh_estimate_chunked(l, 4, 3000, 1, 7, kLambda);
  omp_set_num_threads(3);
  const ShEstimator three = sh_estimate_chunked(l, 4, 3000, 1, 7, kLambda);
  EXPECT_EQ(one.raw(), three.raw());
  EXPECT_EQ(one.incident_count(), 3000u);
  EXPECT_NE(sh_estimate_chunked(l, 4, 3000, 1, 8, kLambda).raw(), one.raw());
  // m_(1,0),(1,0) of a Lambertian reflector is 4/3 times its albedo (docs/theory.md §6.3).
  const ShEstimator big = sh_estimate_chunked(l, 2, 200000, 1, 1, kLambda);
  EXPECT_NEAR(ShBrdf::from_estimator(big).matrix()(sh_odd_index(1, 0), sh_odd_index(1, 0)),
              4.0 / 3 * 0.7, 0.02);
}

TEST(Goniometer, ConeAverageOfKnownFunctions) {
  const Vec3 c = slice_view(0.4, 0.2, SlicePlane::In);
  const Vec3 axis(0, 1, 0);
  EXPECT_NEAR(cone_average([](const Vec3&) { return 2.5; }, c, 0.07, axis), 2.5, 1e-12);
  // A linear function of w averages to its value at the weighted mean direction, which for a
  // narrow cone is the centre to O(half^2).
  const double v = cone_average([](const Vec3& w) { return w.x(); }, c, 0.07, axis);
  EXPECT_NEAR(v, c.x(), 2e-3);
}

TEST(Lobes, FlagsSayWhatEachBrdfIs) {
  const auto mirror = make_brdf(parse_brdf({{"mirror", true}}), parse_material({{"r0", 0.5}}));
  const Vec3 wi(0.6, 0, 0.8);
  const auto s = mirror->sample(wi, 0.3, 0.7, kLambda);
  ASSERT_TRUE(s);
  EXPECT_TRUE(s->delta);
  EXPECT_TRUE(mirror->lobes().delta);
  EXPECT_LT((s->wo - Vec3(-0.6, 0, 0.8)).norm(), 1e-15);
  EXPECT_NEAR(mirror->albedo(wi, kLambda), s->weight, 1e-15);
  const auto ggx = make_brdf(parse_brdf({{"alpha", 0.3}}), MaterialSpec::named_metal("Al"));
  EXPECT_TRUE(ggx->lobes().glossy);
  EXPECT_FALSE(ggx->lobes().delta);
  const auto g = ggx->sample(wi, 0.3, 0.7, kLambda);
  ASSERT_TRUE(g);
  EXPECT_FALSE(g->delta);
  EXPECT_GT(g->pdf, 0);
}
