// Micro-scene geometry and the tracer's energy bookkeeping (no spherical harmonics here).
#include <gtest/gtest.h>

#include <cmath>

#include "microbrdf/error.hpp"
#include "microbrdf/generate.hpp"
#include "microbrdf/microfacet.hpp"
#include "microbrdf/microscene.hpp"
#include "microbrdf/simulate.hpp"
#include "microscene_test_util.hpp"

using namespace microbrdf;
using Vec = Eigen::Vector3d;

namespace {

MicroMaterial lambert(double albedo) {
  MicroMaterial m;
  m.kind = MicroMaterial::Kind::Lambert;
  m.name = "white";
  m.albedo = albedo;
  return m;
}

MicroSceneDesc flat_heightfield(MicroMaterial m, std::size_t n = 16, double dx = 1e-6) {
  MicroSceneDesc d;
  d.width = d.height = n * dx;
  d.materials.push_back(std::move(m));
  Surface s(n, n, dx, dx);
  d.heightfields.push_back({s, 0, false});
  return d;
}

// Albedo of one incident direction: mean exit energy per incident ray.
double albedo(const MicroScene& sc, const Vec& u, int rays, int branches = 1) {
  TraceOptions o;
  o.branches = branches;
  MicroTracer t(sc, o);
  SimRng rng(7, 1);
  TraceCounters c;
  double sum = 0;
  t.trace(
      u, rays, rng, [&](const Vec&, double r) { sum += r; }, c);
  EXPECT_EQ(c.incident_rays, std::uint64_t(rays));
  EXPECT_NEAR(sum, c.energy_out, 1e-9 * rays);
  return sum / rays;
}

}  // namespace

TEST(MicroScene, WhiteLambertPlaneHasAlbedoOne) {
  MicroScene sc(flat_heightfield(lambert(1.0)));
  for (double th : {0.0, 45.0, 85.0}) {
    const Vec u(std::sin(th * M_PI / 180), 0, std::cos(th * M_PI / 180));
    EXPECT_NEAR(albedo(sc, u, 20000, 4), 1.0, 1e-12) << th;
  }
}

TEST(MicroScene, LambertExitsAreCosineDistributed) {
  MicroScene sc(flat_heightfield(lambert(0.5)));
  MicroTracer t(sc, TraceOptions{});
  SimRng rng(3);
  TraceCounters c;
  double sum_cos = 0, sum = 0;
  const int n = 200000;
  t.trace(
      Vec(0, 0, 1), n, rng,
      [&](const Vec& v, double r) {
        sum += r;
        sum_cos += r * v.z();
      },
      c);
  EXPECT_NEAR(sum / n, 0.5, 1e-12);
  // Cosine-distributed: E[cos] = 2/3.
  EXPECT_NEAR(sum_cos / sum, 2.0 / 3.0, 4e-3);
}

TEST(MicroScene, FlatMirrorReflectsIntoTheMirrorDirection) {
  MicroScene sc(flat_heightfield(test_util::mirror_material()));
  MicroTracer t(sc, TraceOptions{});
  SimRng rng(5);
  TraceCounters c;
  const Vec u = Vec(0.3, -0.4, 0.8).normalized();
  const Vec mirror_dir(-u.x(), -u.y(), u.z());
  double worst = 0, sum = 0;
  t.trace(
      u, 5000, rng,
      [&](const Vec& v, double r) {
        worst = std::max(worst, (v - mirror_dir).norm());
        sum += r;
      },
      c);
  EXPECT_LT(worst, 1e-6);
  EXPECT_NEAR(sum, 5000, 1e-9);
}

TEST(MicroScene, RotationTurnsTheScene) {
  auto d = flat_heightfield(test_util::mirror_material());
  d.rotation = M_PI / 2;
  MicroScene sc(std::move(d));
  const Vec w(1, 0, 0);
  EXPECT_NEAR((sc.to_scene(w) - Vec(0, -1, 0)).norm(), 0, 1e-15);
  EXPECT_NEAR((sc.to_brdf(sc.to_scene(Vec(0.3, 0.5, 0.1))) - Vec(0.3, 0.5, 0.1)).norm(), 0, 1e-15);
}

TEST(MicroScene, GaussianMirrorSurfaceConservesEnergyAndNeverLeaks) {
  for (bool grid : {false, true}) {
    const MicroScene sc(test_util::gaussian_mirror_desc(128, 6.5e-6, 10e-6, 65e-6,
                                                        GaussianSurfaceParams{}.seed, grid));
    for (double th : {0.0, 60.0, 85.0}) {
      const Vec u(std::sin(th * M_PI / 180), 0, std::cos(th * M_PI / 180));
      MicroTracer t(sc, TraceOptions{});
      SimRng rng(11);
      TraceCounters c;
      t.trace(
          u, 20000, rng, [](const Vec&, double) {}, c);
      // A closed periodic mirror surface with F = 1 returns every ray.
      EXPECT_EQ(c.energy_down, 0) << th << " grid " << grid;
      EXPECT_EQ(c.capped, 0u);
      EXPECT_NEAR(c.energy_out, 20000, 1e-6) << th << " grid " << grid;
    }
  }
}

TEST(MicroScene, CapsuleGeometryHitsFromOutsideAndInside) {
  MicroSceneDesc d;
  d.width = d.height = 100e-6;
  MicroMaterial glass;
  glass.kind = MicroMaterial::Kind::Dielectric;
  glass.name = "glass";
  glass.eta = 1.5;
  d.materials.push_back(glass);
  d.capsules.push_back({Vec(50e-6, 50e-6, 0), Vec(50e-6, 50e-6, 0), 20e-6, 0});
  MicroScene sc(std::move(d));
  MicroHit h;
  // Straight down through the centre: enters at the top, z = 20 um.
  ASSERT_EQ(sc.trace(Vec(50e-6, 50e-6, sc.zmax()), Vec(0, 0, -1), h), TraceEnd::Hit);
  EXPECT_NEAR(h.p.z(), 20e-6, 1e-10);
  EXPECT_NEAR(h.n.z(), 1, 1e-6);
  // From just inside the top, down: leaves at the bottom.
  ASSERT_EQ(sc.trace(Vec(50e-6, 50e-6, 19e-6), Vec(0, 0, -1), h), TraceEnd::Hit);
  EXPECT_NEAR(h.p.z(), -20e-6, 1e-10);
  EXPECT_NEAR(h.n.z(), -1, 1e-6);
  // Missing it: falls out of the bottom.
  EXPECT_EQ(sc.trace(Vec(5e-6, 5e-6, sc.zmax()), Vec(0, 0, -1), h), TraceEnd::EscapedDown);
}

TEST(MicroScene, PeriodicWrapFindsReplicasAcrossTheTileEdge) {
  MicroSceneDesc d;
  d.width = d.height = 100e-6;
  d.materials.push_back(test_util::mirror_material());
  // A sphere centred on the tile corner: only its replicas cover the other three corners.
  d.capsules.push_back({Vec(0, 0, 0), Vec(0, 0, 0), 20e-6, 0});
  MicroScene sc(std::move(d));
  EXPECT_EQ(sc.capsule_count(), 4u);
  MicroHit h;
  for (Vec o : {Vec(99e-6, 99e-6, 0), Vec(1e-6, 99e-6, 0), Vec(99e-6, 1e-6, 0)}) {
    o.z() = sc.zmax();
    ASSERT_EQ(sc.trace(o, Vec(0, 0, -1), h), TraceEnd::Hit);
    EXPECT_GT(h.p.z(), 19e-6);
  }
  // A grazing ray from the middle of the tile crosses the edge and hits the corner sphere.
  const Vec dir = Vec(1, 1, 0).normalized();
  ASSERT_EQ(sc.trace(Vec(60e-6, 60e-6, 0), dir, h), TraceEnd::Hit);
  EXPECT_NEAR(h.path_length, (Vec(100e-6, 100e-6, 0) - Vec(60e-6, 60e-6, 0)).norm() - 20e-6, 1e-9);
}

TEST(MicroScene, GlassInterfaceReflectsFresnel) {
  // A flat glass surface over nothing: the rays that come back are those reflected, F(theta).
  auto d = flat_heightfield(MicroMaterial{});
  d.materials[0].kind = MicroMaterial::Kind::Dielectric;
  d.materials[0].eta = 1.5;
  MicroScene sc(std::move(d));
  for (double th : {0.0, 60.0, 80.0}) {
    const double c = std::cos(th * M_PI / 180);
    const int n = 100000;
    const double a = albedo(sc, Vec(std::sqrt(1 - c * c), 0, c), n);
    const double f = fresnel_dielectric(c, 1.5);
    EXPECT_NEAR(a, f, 4 * std::sqrt(f * (1 - f) / n) + 1e-12) << th;
  }
}

TEST(MicroScene, GlassLayerOnMirrorFollowsBeerAndFresnel) {
  // Glass of thickness T (Beer coefficient kappa) on a mirror: the returned energy is
  // F + (1 - F)^2 a / (1 - F a), a = exp(-2 kappa T / cos theta_t), F the same both ways.
  const double T = 5e-6, kappa = 1 / 20e-6;
  auto d = flat_heightfield(MicroMaterial{});
  d.materials[0].kind = MicroMaterial::Kind::Dielectric;
  d.materials[0].name = "glass";
  d.materials[0].eta = 1.5;
  d.materials[0].absorption = kappa;
  d.materials.push_back(test_util::mirror_material());
  d.planes.push_back({-T, 1});
  MicroScene sc(std::move(d));
  for (double th : {0.0, 50.0}) {
    const double c = std::cos(th * M_PI / 180), s = std::sqrt(1 - c * c);
    const double ct = std::sqrt(1 - s * s / 2.25);
    const double F = fresnel_dielectric(c, 1.5), a = std::exp(-2 * kappa * T / ct);
    const double expect = F + (1 - F) * (1 - F) * a / (1 - F * a);
    EXPECT_NEAR(albedo(sc, Vec(s, 0, c), 100000), expect, 0.005) << th;
  }
}

TEST(HeGeometricLimit, ReproducesTheReferenceTable) {
  // docs/theory.md §6.7, W92 Fig. 6 recipe: sigma = 10 um, tau = 65 um, F = 1, errata S, sigma_0.
  const double sigma = 10e-6, tau = 65e-6;
  struct Row {
    double ti, tr, value;
  };
  const Row rows[] = {{0, 0, 0.841},   {0, -30, 0.522}, {30, 45, 1.183}, {30, 75, 0.703},
                      {45, 60, 2.040}, {60, 75, 4.865}, {75, 75, 10.04}, {75, 85, 23.44},
                      {60, 15, 0.388}, {45, -30, 0.007}};
  for (const Row& r : rows) {
    const double ti = r.ti * M_PI / 180, tr = r.tr * M_PI / 180;
    const Vec wi(-std::sin(ti), 0, std::cos(ti)), wo(std::sin(tr), 0, std::cos(tr));
    const double v = he1991_geometric_brdf(wi, wo, sigma, tau);
    EXPECT_NEAR(v, r.value, 0.006 * std::max(r.value, 0.2)) << r.ti << " " << r.tr;
  }
  // The printed eq. 25 (no exp(-a^2)) lowers theta_i = 75 deg: 7.40 at theta_r = 75 deg.
  const double t = 75 * M_PI / 180;
  EXPECT_NEAR(he1991_geometric_brdf(Vec(-std::sin(t), 0, std::cos(t)),
                                    Vec(std::sin(t), 0, std::cos(t)), sigma, tau, false),
              7.40, 0.02);
}

TEST(Visibility, TracedG1MatchesSmithAndFtpIsBracketed) {
  // Gaussian surface, sigma = 10 um, tau = 65 um (Beckmann alpha = 0.3077, s = tau/sigma = 6.5).
  const MicroScene sc(test_util::gaussian_mirror_desc(256, 65e-6 / 8, 10e-6, 65e-6));
  BeckmannDistribution beckmann(2 * 10.0 / 65.0);
  for (double deg : {30.0, 60.0, 75.0, 85.0}) {
    const double t = deg * M_PI / 180;
    const auto g = visible_fraction(sc, t, 40000, 3);
    const double smith = beckmann.G1(Vec(std::sin(t), 0, std::cos(t)));
    EXPECT_NEAR(g.value, smith, 0.02 + 4 * g.std_error) << deg;
  }
  // At 80 deg a ray leaving the mean plane escapes more often than Smith's height-averaged G1
  // says for points at any height, and less often than from the top: it lies between
  // 2^-Lambda (Smith at h = 0) within noise.
  const double t = 80 * M_PI / 180;
  const auto f = free_travel_probability(sc, t, 0.05 * 10e-6, 20000, 5);
  const double lambda = beckmann.lambda(Vec(std::sin(t), 0, std::cos(t)));
  EXPECT_NEAR(f.value, std::pow(2.0, -lambda), 0.03 + 4 * f.std_error);
}

TEST(SceneJson, ExampleScenesLoadAndBuild) {
  const std::string dir = std::string(MICROBRDF_TEST_DATA) + "/../../examples/scenes/";
  struct Case {
    const char* file;
    std::size_t triangles, primitives_at_least;
  };
  for (const Case& c :
       {Case{"lambert_plane.json", 0, 1}, Case{"cylinders.json", 0, 11},
        Case{"spheres.json", 0, 26}, Case{"velvet.json", 0, 601}, Case{"cloth_threads.json", 0, 11},
        Case{"gaussian_aluminium.json", 524288, 0}}) {
    MicroScene sc(load_micro_scene(dir + c.file));
    EXPECT_EQ(sc.triangle_count(), c.triangles) << c.file;
    EXPECT_GE(sc.capsule_count(), c.primitives_at_least) << c.file;
    EXPECT_GT(sc.zmax(), sc.zmin()) << c.file;
  }
  // The aluminium facets carry a conductor Fresnel: normal-incidence albedo well below 1.
  MicroScene al(load_micro_scene(dir + "gaussian_aluminium.json"));
  EXPECT_LT(albedo(al, Vec(0, 0, 1), 2000), 0.95);
  EXPECT_GT(albedo(al, Vec(0, 0, 1), 2000), 0.85);
}

TEST(SceneJson, ErrorsNameTheFileAndTheProblem) {
  auto fails_with = [](const char* text, const char* what) {
    try {
      parse_micro_scene(nlohmann::json::parse(text), ".", "scene.json");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const FileError& e) {
      EXPECT_NE(std::string(e.what()).find("scene.json"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  fails_with(R"({"objects": []})", "materials");
  fails_with(R"({"materials": {"a": {"type": "glass"}}, "objects": []})", "type must be");
  fails_with(R"({"tile": "1x1mm", "materials": {"a": {"type": "lambert"}},
                "objects": [{"type": "plane", "z": 0, "material": "a"}]})",
             "unit");
  fails_with(R"({"materials": {"a": {"type": "lambert"}},
                "objects": [{"type": "plane", "z": "0um", "material": "a"}]})",
             "tile");
  fails_with(R"({"tile": "1x1mm", "materials": {"a": {"type": "lambert", "albedo": 2}},
                "objects": []})",
             "albedo");
  fails_with(R"({"tile": "100x100um", "materials": {"a": {"type": "lambert"}},
                "objects": [{"type": "weave", "pitch": "30um", "radius": "10um",
                             "material": "a"}]})",
             "whole number");
}

TEST(SceneJson, CylindersAlongYAreCylindersAlongXTurned) {
  // A scene with cylinders along y equals the along-x scene turned by 90 deg: same albedo for the
  // correspondingly turned light.
  auto scene = [](const char* extra) {
    const std::string text = std::string(R"({"tile": "120x120um",
      "materials": {"m": {"type": "mirror", "metal": "Al"}, "b": {"type": "absorber"}},
      "objects": [{"type": "cylinders", "radius": "5um", "pitch": "12um", "material": "m")") +
                             extra + R"(}, {"type": "plane", "z": "0um", "material": "b"}]})";
    return MicroScene(parse_micro_scene(nlohmann::json::parse(text), ".", "t.json"));
  };
  MicroScene x = scene(""), y = scene(R"(, "angle": "90deg")");
  EXPECT_EQ(x.capsule_count(), y.capsule_count());
  const double ax = albedo(x, Vec(0.6, 0, 0.8), 20000), ay = albedo(y, Vec(0, 0.6, 0.8), 20000);
  const double across = albedo(y, Vec(0.6, 0, 0.8), 20000);
  EXPECT_NEAR(ax, ay, 0.01);
  EXPECT_GT(std::abs(ax - across), 0.02);  // anisotropic
}

TEST(MicroScene, OriginsJustOutsideTheTileAreWrappedIn) {
  // A reflection next to a wall offsets the new origin by epsilon, possibly across the wall; the
  // query must wrap it (this once let 1 ray in 2 million fall through a Gaussian surface).
  MicroScene sc(flat_heightfield(test_util::mirror_material()));
  MicroHit h;
  const Vec d = Vec(-0.6, 0, -0.8);
  ASSERT_EQ(sc.trace(Vec(-1e-9, 5e-6, 1e-6), d, h), TraceEnd::Hit);
  EXPECT_NEAR(h.p.x(), sc.width() - 1e-9 - 0.75e-6, 1e-10);
  EXPECT_NEAR(h.p.z(), 0, 1e-12);
  EXPECT_NEAR(h.path_length, 1.25e-6, 1e-10);
}

// The escape bound answers only for rays that truly leave: every upward mirror ray it clears must
// leave the top when traced through Embree (rough surfaces, steep facets, grazing exits, and a
// tile that is not a whole number of bound blocks), and it answers a good share of them.
TEST(MicroScene, EscapeBoundNeverClearsARayThatHitsTheSurface) {
  struct Case {
    std::size_t n;
    double sigma, tau, share;  // share: the least fraction of upward rays it must answer
    bool grid;
  };
  for (const Case& cs : {Case{96, 10e-6, 65e-6, 0.7, false}, Case{100, 20e-6, 30e-6, 0.01, false},
                         Case{64, 3e-6, 40e-6, 0.8, false}, Case{90, 10e-6, 40e-6, 0.5, true}}) {
    MicroScene sc(test_util::gaussian_mirror_desc(cs.n, 65e-6 / 8, cs.sigma, cs.tau, 7, cs.grid));
    ASSERT_TRUE(sc.has_escape_bound());
    const double eps = sc.epsilon();
    SimRng rng(3, cs.n);
    std::size_t upward = 0, cleared = 0, hits_after_clear = 0;
    for (int k = 0; k < 60000; ++k) {
      const Vec u = uniform_hemisphere(rng.uniform(), rng.uniform());
      const Vec o(rng.uniform() * sc.width(), rng.uniform() * sc.height(), sc.zmax());
      MicroHit h;
      if (sc.trace(o, -u, h) != TraceEnd::Hit) continue;
      const Vec d = (-u + 2 * u.dot(h.n) * h.n).normalized();
      if (!(d.z() > 0)) continue;
      ++upward;
      if (!sc.clears_upward(h.p, h.n, d)) continue;
      ++cleared;
      MicroHit h2;
      if (sc.trace(h.p + eps * h.n, d, h2) != TraceEnd::EscapedUp) ++hits_after_clear;
    }
    EXPECT_EQ(hits_after_clear, 0u) << cs.sigma << " " << cs.tau;
    EXPECT_GT(double(cleared), cs.share * double(upward)) << cs.sigma << " " << cs.tau;
  }
  // Scenes with analytic primitives (or several height fields) never use it.
  MicroSceneDesc d;
  d.width = d.height = 100e-6;
  d.materials.push_back(test_util::mirror_material());
  d.capsules.push_back({Vec(50e-6, 50e-6, 0), Vec(50e-6, 50e-6, 0), 20e-6, 0});
  MicroScene caps(std::move(d));
  EXPECT_FALSE(caps.has_escape_bound());
  EXPECT_FALSE(caps.clears_upward(Vec(50e-6, 50e-6, 20e-6), Vec(0, 0, 1), Vec(0, 0, 1)));
}
