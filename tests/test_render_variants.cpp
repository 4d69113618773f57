// Several materials along shared paths (render_variants): each image estimates what render()
// gives for that material alone, one variant is render() bit for bit, and the images' noise is
// correlated, so differences between variants are cleaner than between independent renders.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "microbrdf/error.hpp"
#include "microbrdf/lambertian_brdf.hpp"
#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/mirror_brdf.hpp"
#include "microbrdf/render.hpp"
#include "microbrdf/spectrum.hpp"
#include "microbrdf/tabulated_distribution.hpp"
#include "render/material.hpp"
#include "render_test_util.hpp"

using namespace microbrdf;

namespace {

using Materials = std::vector<std::shared_ptr<const Svbrdf>>;

Materials one(std::shared_ptr<const Brdf> b) {
  return {std::make_shared<UniformSvbrdf>(std::move(b))};
}

std::shared_ptr<const Brdf> metal_brdf(std::shared_ptr<const MicrofacetDistribution> d,
                                       const char* name) {
  return std::make_shared<MicrofacetBrdf>(std::move(d),
                                          std::make_shared<ConductorFresnel>(metal(name)));
}

RenderOptions options(int size, int spp) {
  RenderOptions o;
  o.width = o.height = size;
  o.spp = spp;
  o.threads = 2;
  return o;
}

using test::mean_rgb;

double rms_difference(const RenderImage& a, const RenderImage& b, const RenderImage& c,
                      const RenderImage& d) {
  double s = 0;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) {
    const double x = (double(a.rgb[i]) - b.rgb[i]) - (double(c.rgb[i]) - d.rgb[i]);
    s += x * x;
  }
  return std::sqrt(s / double(a.rgb.size()));
}

// A dim uniform sky and a sphere light: glossy and diffuse lobes both meet light everywhere.
RenderLights sky_and_sphere() {
  RenderLights l;
  l.uniform_white_env = true;
  l.envmap_scale = 0.5;
  l.spheres.push_back({Eigen::Vector3d(3, 3, 3), 1.5, Eigen::Vector3d(4, 4, 4)});
  return l;
}

}  // namespace

TEST(RenderVariants, OneVariantIsRenderBitForBit) {
  RenderScene sc;
  sc.kind = PreviewScene::Cylinders;
  const auto b = metal_brdf(std::make_shared<BeckmannDistribution>(0.05, 0.2), "Al");
  auto o = options(16, 8);
  const RenderImage a = render(sc, one(b), sky_and_sphere(), o);
  o.variant_weights = {3.0};  // one variant: its weight changes nothing
  const auto v = render_variants(sc, {one(b)}, sky_and_sphere(), o);
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(a.rgb, v[0].rgb);
}

TEST(RenderVariants, EachVariantEstimatesItsOwnRender) {
  // Four lobes along the same paths - glossy anisotropic, rough, diffuse and a delta mirror -
  // against each one rendered alone (same seed, same spp): image means within 1% (measured: 0.35%;
  // the noise of a 16^2 x 512 spp mean is a few tenths of a percent). Then the same with the glossy
  // lobe at mixture weight 0: the Lambertian and rough lobes reach every direction, so its image
  // must stay unbiased although its own sampler is never used.
  RenderScene sc;
  sc.kind = PreviewScene::Sphere;
  const RenderLights l = sky_and_sphere();
  const std::vector<std::shared_ptr<const Brdf>> brdfs = {
      metal_brdf(std::make_shared<GgxDistribution>(0.08, 0.3), "Cu"),
      metal_brdf(std::make_shared<BeckmannDistribution>(0.4), "Au"),
      std::make_shared<LambertianBrdf>(0.5),
      std::make_shared<SpecularMirrorBrdf>(std::make_shared<ConductorFresnel>(metal("Ag")))};
  std::vector<Materials> variants;
  for (const auto& b : brdfs) variants.push_back(one(b));
  auto o = options(16, 512);
  std::vector<Eigen::Vector3d> alone;
  for (const auto& b : brdfs) alone.push_back(mean_rgb(render(sc, one(b), l, o)));
  for (const std::vector<double>& weights :
       {std::vector<double>{}, std::vector<double>{0.0, 1.0, 1.0, 1.0}}) {
    o.variant_weights = weights;
    const auto imgs = render_variants(sc, variants, l, o);
    ASSERT_EQ(imgs.size(), brdfs.size());
    for (std::size_t v = 0; v < brdfs.size(); ++v) {
      const Eigen::Vector3d m = mean_rgb(imgs[v]);
      for (int ch = 0; ch < 3; ++ch)
        EXPECT_NEAR(m[ch] / alone[v][ch], 1.0, 0.01)
            << "variant " << v << " channel " << ch << (weights.empty() ? "" : ", weight 0 first");
    }
  }
}

TEST(RenderVariants, SameImagesWhateverTheThreads) {
  RenderScene sc;
  sc.kind = PreviewScene::Cylinders;
  RenderLights l;
  l.envmap_path = std::string(MICROBRDF_DATA) + "/envmaps/blender_courtyard.exr";
  const std::vector<Materials> variants = {
      one(metal_brdf(std::make_shared<GgxDistribution>(0.1, 0.3), "Cu")),
      one(metal_brdf(std::make_shared<BeckmannDistribution>(0.12, 0.35), "Cu"))};
  auto o = options(16, 4);
  o.threads = 1;
  const auto a = render_variants(sc, variants, l, o);
  o.threads = 2;
  const auto b = render_variants(sc, variants, l, o);
  EXPECT_EQ(a[0].rgb, b[0].rgb);
  EXPECT_EQ(a[1].rgb, b[1].rgb);
  EXPECT_NE(a[0].rgb, a[1].rgb);
}

TEST(RenderVariants, DifferencesAreLessNoisyThanBetweenSeparateRenders) {
  // Two close lobes under the courtyard map, plain Monte Carlo: the difference of the two
  // images from one shared-path render against the same difference from renders with their
  // own seeds, each difference taken against a high-spp estimate of the true difference. The
  // shared paths cancel most of the noise (measured: 7.7x lower RMS error).
  RenderScene sc;
  sc.kind = PreviewScene::Cylinders;
  RenderLights l;
  l.envmap_path = std::string(MICROBRDF_DATA) + "/envmaps/blender_courtyard.exr";
  const auto b0 = metal_brdf(std::make_shared<GgxDistribution>(0.1, 0.3), "Cu");
  const auto b1 = metal_brdf(std::make_shared<GgxDistribution>(0.12, 0.33), "Cu");
  auto o = options(24, 16);
  o.sampler = RenderSampler::Independent;
  o.direct = DirectLight::Mis;  // the estimator variants use: the same for both sides
  auto ref_o = o;
  ref_o.spp = 512;
  const auto ref = render_variants(sc, {one(b0), one(b1)}, l, ref_o);
  const auto joint = render_variants(sc, {one(b0), one(b1)}, l, o);
  const RenderImage a = render(sc, one(b0), l, o);
  o.seed = 7;
  const RenderImage b = render(sc, one(b1), l, o);
  const double e_joint = rms_difference(joint[0], joint[1], ref[0], ref[1]);
  const double e_separate = rms_difference(a, b, ref[0], ref[1]);
  EXPECT_LT(e_joint, 0.25 * e_separate) << e_joint << " vs " << e_separate;
}

TEST(RenderVariants, BadVariantListsAreRefused) {
  RenderScene sc;
  const auto b = one(std::make_shared<LambertianBrdf>(0.5));
  const RenderLights l = sky_and_sphere();
  auto o = options(4, 1);
  EXPECT_THROW(render_variants(sc, {}, l, o), InputError);
  EXPECT_THROW(render_variants(sc, std::vector<Materials>(kMaxRenderVariants + 1, b), l, o),
               InputError);
  o.variant_weights = {1.0};
  EXPECT_THROW(render_variants(sc, {b, b}, l, o), InputError);
  o.variant_weights = {1.0, -1.0};
  EXPECT_THROW(render_variants(sc, {b, b}, l, o), InputError);
  o.variant_weights = {0.0, 0.0};
  EXPECT_THROW(render_variants(sc, {b, b}, l, o), InputError);
  o.variant_weights = {1.0, 0.0};
  EXPECT_EQ(render_variants(sc, {b, b}, l, o).size(), 2u);
}

TEST(RenderVariants, SamplingDensityEqualsEvalsDensityWhereFIsNotZero) {
  // SpectralMaterial::sampling_pdf (what a mixture of samplers needs for every variant) against
  // the density eval() returns with f, for an analytic and a tabulated NDF, on a spiral of
  // direction pairs.
  const auto cu = std::make_shared<ConductorFresnel>(metal("Cu"));
  const TabulatedNdf table = tabulate(BeckmannDistribution(0.15, 0.3), "beckmann", 129);
  const std::vector<std::shared_ptr<const Brdf>> brdfs = {
      std::make_shared<MicrofacetBrdf>(std::make_shared<GgxDistribution>(0.2, 0.4), cu),
      std::make_shared<MicrofacetBrdf>(std::make_shared<TabulatedDistribution>(table), cu)};
  for (const auto& b : brdfs) {
    const pt::SpectralMaterial m(std::make_shared<UniformSvbrdf>(b));
    const double lambda[1] = {555e-9};
    pt::SpectralMaterial::Wavelengths w;
    m.prepare(lambda, 1, w);
    int compared = 0;
    for (int i = 0; i < 64; ++i) {
      const double ti = 0.05 + 0.022 * i, pi = 0.37 * i, to = 1.45 - 0.02 * i, po = 2.9 + 0.41 * i;
      const Vec3 wi(std::sin(ti) * std::cos(pi), std::sin(ti) * std::sin(pi), std::cos(ti));
      const Vec3 wo(std::sin(to) * std::cos(po), std::sin(to) * std::sin(po), std::cos(to));
      const auto view = m.view(wo);
      double f[1], pdf = 0;
      if (!m.eval(0, 0, view, wi, w, f, &pdf)) continue;
      ++compared;
      EXPECT_NEAR(m.sampling_pdf(0, 0, view, wi), pdf, 1e-12 * pdf) << b->describe() << " " << i;
    }
    EXPECT_GT(compared, 20) << b->describe();
  }
}

namespace {

RenderLights envmap(const char* name, double scale = 1) {
  RenderLights l;
  l.envmap_path = std::string(MICROBRDF_DATA) + "/envmaps/" + name;
  l.envmap_scale = scale;
  return l;
}

}  // namespace

TEST(RenderLightSets, EachSetEstimatesItsOwnRender) {
  // Two lobes along shared paths under the courtyard, the first also under the studio map with
  // a point light and under the interior map: every image against its BRDF rendered alone under
  // its lights, with the estimator the shared passes use (MIS): image means within 1.5% (the
  // noise of a 16^2 x 256 spp mean is a few tenths of a percent). Then with the first lobe at
  // mixture weight 0: the further sets then rely on their light samples alone, still unbiased.
  RenderScene sc;
  sc.kind = PreviewScene::Cylinders;
  RenderLights studio = envmap("blender_studio.exr");
  studio.points.push_back({Eigen::Vector3d(2, 4, 3), Eigen::Vector3d(3, 3, 3)});
  const std::vector<RenderLights> sets = {envmap("blender_courtyard.exr"), studio,
                                          envmap("blender_interior.exr")};
  const std::vector<std::shared_ptr<const Brdf>> brdfs = {
      metal_brdf(std::make_shared<GgxDistribution>(0.1, 0.3), "Cu"),
      metal_brdf(std::make_shared<BeckmannDistribution>(0.3), "Au")};
  std::vector<Materials> variants;
  for (const auto& b : brdfs) variants.push_back(one(b));
  auto o = options(16, 256);
  o.direct = DirectLight::Mis;
  // (image, set, variant): the variants under the first set, then the first under the others
  const std::vector<std::array<int, 3>> layout = {{0, 0, 0}, {1, 0, 1}, {2, 1, 0}, {3, 2, 0}};
  std::vector<Eigen::Vector3d> alone;
  for (const auto& [i, l, v] : layout)
    alone.push_back(mean_rgb(render(sc, one(brdfs[v]), sets[l], o)));
  for (const std::vector<double>& weights :
       {std::vector<double>{}, std::vector<double>{0.0, 1.0}}) {
    o.variant_weights = weights;
    const auto imgs = render_light_sets(sc, variants, sets, o);
    ASSERT_EQ(imgs.size(), layout.size());
    for (const auto& [i, l, v] : layout) {
      // (weight 0: the first lobe's image under the courtyard's sun, drawn by the rough lobe's
      // sampler alone, is unbiased but too noisy for 1.5%; render_variants' own tests cover it)
      if (!weights.empty() && i == 0) continue;
      const Eigen::Vector3d m = mean_rgb(imgs[i]);
      for (int ch = 0; ch < 3; ++ch)
        EXPECT_NEAR(m[ch] / alone[i][ch], 1.0, 0.015)
            << "set " << l << " variant " << v << " channel " << ch
            << (weights.empty() ? "" : ", first weight 0");
      EXPECT_NE(imgs[i].settings.find("one of 3 light sets"), std::string::npos);
    }
  }
}

TEST(RenderLightSets, ASecondSetAtTwiceTheRadianceAndThreadsDoNotMatter) {
  RenderScene sc;
  sc.kind = PreviewScene::Sphere;
  const auto b = metal_brdf(std::make_shared<GgxDistribution>(0.15, 0.3), "Cu");
  const auto c = metal_brdf(std::make_shared<BeckmannDistribution>(0.2), "Al");
  auto o = options(12, 4);
  const RenderLights court = envmap("blender_courtyard.exr");
  // (one set: render_variants is this function; tests/cli/render_golden.sh pins single renders
  // to the images of earlier builds)
  EXPECT_EQ(render_light_sets(sc, {one(b), one(c)}, {court}, o).size(), 2u);
  // A second set at twice the first's radiance: BRDF-sampled emission is the same along the
  // same paths, light samples differ; both images agree in the mean, and neither depends on the
  // thread count.
  const std::vector<RenderLights> sets = {court, envmap("blender_courtyard.exr", 2.0)};
  o.threads = 1;
  const auto a1 = render_light_sets(sc, {one(b)}, sets, o);
  o.threads = 2;
  const auto a2 = render_light_sets(sc, {one(b)}, sets, o);
  EXPECT_EQ(a1[0].rgb, a2[0].rgb);
  EXPECT_EQ(a1[1].rgb, a2[1].rgb);
  o.spp = 256;
  const auto big = render_light_sets(sc, {one(b)}, sets, o);
  const Eigen::Vector3d m0 = mean_rgb(big[0]), m1 = mean_rgb(big[1]);
  for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(m1[ch] / (2 * m0[ch]), 1.0, 0.01) << ch;
}

TEST(RenderLightSets, BadSetListsAreRefused) {
  RenderScene sc;
  const auto b = one(std::make_shared<LambertianBrdf>(0.5));
  auto o = options(4, 1);
  EXPECT_THROW(render_light_sets(sc, {b}, {}, o), InputError);
  const RenderLights court = envmap("blender_courtyard.exr");
  EXPECT_THROW(
      render_light_sets(sc, {b}, std::vector<RenderLights>(kMaxRenderLightSets + 1, court), o),
      InputError);
  // Area lights end a path in their own set only: refused with several sets, named.
  try {
    render_light_sets(sc, {b}, {court, sky_and_sphere()}, o);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("light set 2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(render_light_sets(sc, {b}, {court, RenderLights{}}, o), InputError);
  EXPECT_EQ(render_light_sets(sc, {b}, {court, court}, o).size(), 2u);
  EXPECT_EQ(render_light_sets(sc, {b, b, b}, {court, court}, o).size(), 4u);
}
