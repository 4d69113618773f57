// The renderer's micro-scenes (RenderScene::micro_scene): the periodic tile of a `simulate`
// scene drawn as geometry on the plate, at the scale and orientation asked for.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "microbrdf/error.hpp"
#include "microbrdf/microscene.hpp"
#include "microbrdf/render.hpp"
#include "microbrdf/sh_brdf.hpp"
#include "microbrdf/simulate.hpp"
#include "microscene_test_util.hpp"
#include "render/micro_patch.hpp"
#include "render_test_util.hpp"

namespace microbrdf {
namespace {

using V3 = Eigen::Vector3d;

constexpr double kTile = 120e-6, kRadius = 5e-6, kPitch = 12e-6;

// Ten parallel cylinders (radius 5 um, axes 5 um up, no jitter) along the scene's x axis over a
// plane: the geometry of examples/scenes/cylinders.json without its jitter.
MicroSceneDesc cylinders(MicroMaterial cyl, MicroMaterial base) {
  MicroSceneDesc d;
  d.name = "test-cylinders";
  d.width = d.height = kTile;
  cyl.name = "cylinder";
  base.name = "base";
  d.materials = {cyl, base};
  add_cylinders(d, kRadius, 10, kRadius, 0.0, 1, 0);
  d.planes.push_back({0.0, 1});
  return d;
}

MicroMaterial lambert(double albedo) { return test_util::lambert_material(albedo); }

// Height (m) of the cylinder array above scene coordinate y: written from the geometry (centres
// at (k + 1/2) pitch), not from the tracer.
double expected_height(double y_scene) {
  y_scene -= kTile * std::floor(y_scene / kTile);
  const double k = std::floor(y_scene / kPitch);
  const double dy = y_scene - (k + 0.5) * kPitch;
  return std::abs(dy) < kRadius ? kRadius + std::sqrt(kRadius * kRadius - dy * dy) : 0.0;
}

TEST(RenderMicroScene, RaysStraightDownMeetTheCylindersWhereTheyAre) {
  const auto desc = cylinders(lambert(1), lambert(0.5));
  const double tiles = 4, mpu = tiles * kTile / 2;  // metres per world unit
  for (double angle : {0.0, M_PI / 2}) {
    const pt::MicroPatch patch(desc, tiles, 1.0, angle);
    EXPECT_DOUBLE_EQ(patch.metres_per_unit(), mpu);
    int on_cylinders = 0;
    for (int i = 0; i < 997; ++i) {
      const double s = -0.99 + 1.98 * i / 996;  // world coordinate across the cylinders
      // Angle 0: the axes run along world x, scene y = -world z. Angle 90 deg: the scene's x
      // axis is the plate's x turned 90 deg about the normal (world -z), scene y = -world x.
      const V3 o = angle == 0 ? V3(0.3, 1, s) : V3(s, 1, 0.3);
      pt::MicroPatchHit h;
      ASSERT_TRUE(patch.intersect(o, V3(0, -1, 0), 1e30, h)) << s;
      const double want = expected_height(-s * mpu);
      EXPECT_NEAR(h.p.y() * mpu, want, 5e-9) << "angle " << angle << " at " << s;
      EXPECT_NEAR(h.t, 1 - want / mpu, 1e-6);
      on_cylinders += want > 0;
      if (want > 0) {  // the normal of a cylinder along the axis tx: no component along it
        const V3 axis = angle == 0 ? V3(1, 0, 0) : V3(0, 0, -1);
        EXPECT_NEAR(h.n.dot(axis), 0, 1e-6);
        EXPECT_NEAR(std::abs(h.t_dir.dot(axis)), 1, 1e-6);  // the tangent is the axis
        EXPECT_EQ(h.material, 0);
      } else {
        EXPECT_EQ(h.material, 1);
        EXPECT_NEAR(h.n.y(), 1, 1e-12);
      }
    }
    // 5/6 of the width is covered by cylinders (diameter 10 of the pitch 12 um).
    EXPECT_NEAR(on_cylinders / 997.0, 10.0 / 12.0, 0.01);
    // Off the plate's square there is nothing; a ray along the plate above the cylinders
    // misses too.
    pt::MicroPatchHit h;
    EXPECT_FALSE(patch.intersect(V3(1.2, 1, 0), V3(0, -1, 0), 1e30, h));
    EXPECT_FALSE(patch.intersect(V3(-3, 11e-6 / mpu, 0.01), V3(1, 0, 0), 1e30, h));
    // tfar before the surface: no hit.
    EXPECT_FALSE(patch.intersect(V3(0.3, 1, 0.3), V3(0, -1, 0), 0.5, h));
  }
}

TEST(RenderMicroScene, WhiteFurnaceIsOne) {
  // White Lambertian cylinders on a white plane under a uniform white sky: every path keeps its
  // weight until it escapes, so the radiance is 1 everywhere, at any scale (a ray that starts
  // inside a surface or misses one it should hit would darken it).
  const auto desc = std::make_shared<MicroSceneDesc>(cylinders(lambert(1), lambert(1)));
  RenderLights l;
  l.uniform_white_env = true;
  for (double tiles : {2.0, 50.0}) {
    RenderScene sc;
    sc.kind = PreviewScene::Plate;
    sc.micro_scene = desc;
    sc.micro_tiles = tiles;
    RenderOptions o;
    o.width = o.height = 24;
    o.spp = 64;
    o.threads = 2;
    o.max_depth = 200;
    const auto img = render(sc, micro_scene_materials(*desc), l, o);
    double m = 0;
    for (int y = 4; y < 20; ++y)
      for (int x = 4; x < 20; ++x) m += img.rgb[(y * 24 + x) * 3 + 1] / 256.0;
    EXPECT_NEAR(m, 1.0, 0.01) << tiles << " tiles";
  }
}

TEST(RenderMicroScene, FarAwayALambertianPlaneSceneIsTheFlatPlate) {
  // A micro-scene that is a plane of albedo 0.4 seen far away is the flat plate with the same
  // Lambertian BRDF, under the plate's own light: the same light, camera and pixels.
  auto desc = std::make_shared<MicroSceneDesc>();
  desc->name = "plane";
  desc->width = desc->height = 1e-4;
  desc->materials = {lambert(0.4)};
  desc->materials[0].name = "grey";
  desc->planes.push_back({0.0, 0});
  RenderScene sc;
  sc.kind = PreviewScene::Plate;
  RenderLights l;
  add_default_light_if_none(l, sc.kind);
  RenderOptions o;
  o.width = o.height = 16;
  o.spp = 16;
  o.threads = 2;
  const auto flat = render(sc, micro_scene_materials(*desc), l, o);
  sc.micro_scene = desc;
  sc.micro_tiles = 1000;
  const auto micro = render(sc, micro_scene_materials(*desc), l, o);
  const double a = test::mean_rgb(flat)[1], b = test::mean_rgb(micro)[1];
  EXPECT_GT(a, 0.05);
  EXPECT_NEAR(b / a, 1.0, 1e-3);
}

TEST(RenderMicroScene, FarAwayTheCylindersLookLikeTheirSimulatedBrdf) {
  // W92 Fig. 7's check, small: the cylinders of examples/scenes/cylinders.json (rough aluminium
  // on a black base) drawn as geometry far away (200 tiles: 2000 cylinders across 16 pixels)
  // and the plate with the SH BRDF simulated from the same scene, under the plate's disk light,
  // axes across and along the screen: the same mean radiance. (The full-size check, with the
  // figure, is scripts/make-westin-fig7.sh, run by docs/westin.md's test.)
  const auto desc = std::make_shared<MicroSceneDesc>(
      load_micro_scene(std::string(MICROBRDF_DATA) + "/../examples/scenes/cylinders.json"));
  SimulateOptions so;
  so.lmax = 16;
  // The matrix of docs/westin.md (4 10^6 rays of 16 points per direction): with 2.5 10^5 rays
  // its Monte Carlo noise alone moves the plate by 7 %.
  so.incident_directions = 4000000 / 16;
  so.threads = 2;
  const auto sh = std::make_shared<ShBrdf>(ShBrdf::from_estimator(simulate(MicroScene(*desc), so)));
  RenderLights l;
  add_default_light_if_none(l, PreviewScene::Plate);
  RenderOptions o;
  o.width = o.height = 16;
  o.threads = 2;
  o.direct = DirectLight::Mis;
  for (double angle : {0.0, M_PI / 2}) {
    RenderScene sc;
    sc.kind = PreviewScene::Plate;
    sc.brush_angle_rad = angle;
    o.spp = 16;
    const double plate = test::mean_rgb(render(sc, {std::make_shared<UniformSvbrdf>(sh)}, l, o))[1];
    sc.micro_scene = desc;
    sc.micro_tiles = 200;
    o.spp = 256;
    const double geometry = test::mean_rgb(render(sc, micro_scene_materials(*desc), l, o))[1];
    EXPECT_NEAR(geometry / plate, 1.0, 0.05) << "brush angle " << angle;
    std::printf("angle %g: geometry %.4f, SH plate %.4f\n", angle, geometry, plate);
  }
}

TEST(RenderMicroScene, MaterialsFollowTheScene) {
  MicroSceneDesc d;
  MicroMaterial mirror;
  mirror.kind = MicroMaterial::Kind::Mirror;
  mirror.name = "mirror";
  MicroMaterial black;
  black.name = "black";  // Kind::Absorber
  d.materials = {mirror, lambert(0.3), black};
  const auto m = micro_scene_materials(d);
  ASSERT_EQ(m.size(), 3u);
  const Vec3 wi(0.3, 0.1, std::sqrt(1 - 0.1)), wo(-0.2, 0.4, std::sqrt(1 - 0.2));
  // The mirror: a delta lobe (eval 0, the sample carries the weight F = 1, no Fresnel given).
  EXPECT_EQ(m[0]->eval(0, 0, wi, wo, 550e-9), 0);
  const auto s = m[0]->sample(0, 0, wo, 0.5, 0.5, 550e-9);
  ASSERT_TRUE(s.has_value());
  EXPECT_NEAR(s->weight, 1, 1e-12);
  EXPECT_NEAR(m[1]->eval(0, 0, wi, wo, 550e-9), 0.3 / M_PI, 1e-12);
  EXPECT_EQ(m[2]->eval(0, 0, wi, wo, 550e-9), 0);
  MicroMaterial glass;
  glass.kind = MicroMaterial::Kind::Dielectric;
  glass.name = "glass";
  d.materials.push_back(glass);
  EXPECT_THROW(micro_scene_materials(d), InputError);
}

TEST(RenderMicroScene, DrawnOnThePlateOnly) {
  RenderScene sc;
  sc.kind = PreviewScene::Sphere;
  sc.micro_scene = std::make_shared<MicroSceneDesc>(cylinders(lambert(1), lambert(1)));
  RenderLights l;
  l.uniform_white_env = true;
  RenderOptions o;
  o.width = o.height = 4;
  o.spp = 1;
  EXPECT_THROW(render(sc, micro_scene_materials(*sc.micro_scene), l, o), InputError);
  sc.kind = PreviewScene::Plate;
  sc.micro_tiles = 0;
  EXPECT_THROW(render(sc, micro_scene_materials(*sc.micro_scene), l, o), InputError);
}

}  // namespace
}  // namespace microbrdf
