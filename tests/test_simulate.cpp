// The W92 estimator on traced micro-scenes: constants (Lambertian, microfacet plane against the
// direct projection), hierarchical reuse, anisotropy of cylinders, Q ~ N^-1/2, determinism.
#include <gtest/gtest.h>

#include <cmath>

#include "microbrdf/brdf.hpp"
#include "microbrdf/generate.hpp"
#include "microbrdf/microfacet.hpp"
#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/sh_brdf.hpp"
#include "microbrdf/simulate.hpp"
#include "microscene_test_util.hpp"

using namespace microbrdf;
using Vec = Eigen::Vector3d;

namespace {

constexpr double kDeg = M_PI / 180;

MicroSceneDesc flat(MicroMaterial m) {
  MicroSceneDesc d;
  d.width = d.height = 16e-6;
  m.name =
      std::string(1, 'm');  // (operator=(const char*) trips a GCC 12 -Wrestrict false positive)
  d.materials.push_back(std::move(m));
  d.heightfields.push_back({Surface(16, 16, 1e-6, 1e-6), 0, false});
  return d;
}

MicroMaterial lambert(double a) { return test_util::lambert_material(a); }

MicroMaterial microfacet(double alpha) {
  MicroMaterial m;
  m.kind = MicroMaterial::Kind::Brdf;
  m.brdf = std::make_shared<MicrofacetBrdf>(std::make_shared<BeckmannDistribution>(alpha),
                                            std::make_shared<PerfectMirrorFresnel>());
  return m;
}

Vec dir(double theta_deg, double phi_deg) {
  const double t = theta_deg * kDeg, p = phi_deg * kDeg;
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

}  // namespace

TEST(Simulate, WhiteLambertPlaneGivesTheExactMatrix) {
  // docs/theory.md §6.3: f = cos cos / pi -> only m_(1,0),(1,0) = 4/3 is non-zero.
  MicroScene sc(flat(lambert(1.0)));
  SimulateOptions o;
  o.lmax = 6;
  o.incident_directions = 60000;
  o.points = 2;
  o.trace.branches = 4;
  SimulateStats st;
  const ShBrdf b = ShBrdf::from_estimator(simulate(sc, o, &st));
  EXPECT_NEAR(st.counters.energy_out / st.counters.incident_rays, 1.0, 1e-12);
  const auto& basis = b.basis();
  for (int j = 0; j < basis.size(); ++j)
    for (int k = 0; k < basis.size(); ++k) {
      const bool main = basis.l(j) == 1 && basis.m(j) == 0 && basis.l(k) == 1 && basis.m(k) == 0;
      EXPECT_NEAR(b.matrix()(j, k), main ? 4.0 / 3.0 : 0.0, main ? 0.01 : 0.02) << j << " " << k;
    }
  for (double t : {0.0, 40.0, 70.0}) EXPECT_NEAR(b.albedo(dir(t, 30)), 1.0, 0.01) << t;
}

TEST(Simulate, MicrofacetPlaneMatchesTheDirectProjection) {
  // A flat plane whose micro-BRDF is Beckmann: the simulated matrix must be the projection of
  // that BRDF (same constants, same basis), up to Monte Carlo noise.
  const double alpha = 0.4;
  auto m = microfacet(alpha);
  const auto ref = ShBrdf::project(*m.brdf, 6, 550e-9, 48);
  MicroScene sc(flat(m));
  SimulateOptions o;
  o.lmax = 6;
  o.incident_directions = 30000;
  o.points = 8;
  const ShBrdf b = ShBrdf::from_estimator(simulate(sc, o));
  const double err = (b.matrix() - ref.matrix()).norm() / ref.matrix().norm();
  EXPECT_LT(err, 0.03);  // noise: 0.08 / 0.045 / 0.021 at 1 / 4 / 16 points (lmax 8)
  for (double ti : {0.0, 45.0}) {
    const Vec wi = dir(ti, 180), wo = dir(ti, 0);
    EXPECT_NEAR(b.cosine_weighted(wi, wo) / ref.cosine_weighted(wi, wo), 1.0, 0.05) << ti;
  }
}

TEST(Simulate, HierarchicalReuseOfASimulatedBrdf) {
  // A plane carrying a previously simulated ShBrdf reproduces it (W92 section 5.4).
  auto m = microfacet(0.4);
  auto sh = std::make_shared<ShBrdf>(ShBrdf::project(*m.brdf, 8, 550e-9));
  MicroMaterial mm;
  mm.kind = MicroMaterial::Kind::Brdf;
  mm.brdf = sh;
  MicroScene sc(flat(mm));
  SimulateOptions o;
  o.lmax = 8;
  o.incident_directions = 40000;
  o.points = 4;
  const ShBrdf b = ShBrdf::from_estimator(simulate(sc, o));
  EXPECT_LT((b.matrix() - sh->matrix()).norm() / sh->matrix().norm(), 0.05);
}

TEST(Simulate, DeterministicForASeedAndThreadCount) {
  MicroScene sc(flat(lambert(0.7)));
  SimulateOptions o;
  o.lmax = 5;
  o.incident_directions = 3000;
  o.points = 2;
  o.threads = 2;
  const auto a = simulate(sc, o).raw(), b = simulate(sc, o).raw();
  EXPECT_EQ((a - b).cwiseAbs().maxCoeff(), 0.0);
  o.threads = 1;
  const auto c = simulate(sc, o).raw();
  EXPECT_EQ((a - c).cwiseAbs().maxCoeff(), 0.0);  // blocks merged in block order
  o.seed = 2;
  EXPECT_GT((simulate(sc, o).raw() - c).cwiseAbs().maxCoeff(), 1e-4);
}

// A rough mirror height field (escape rays decided by the bound or by Embree, exits projected
// eight at a time, batched outer products): the same matrix bit for bit with 1, 2 and 3 threads.
TEST(Simulate, GaussianMirrorMatrixIndependentOfTheThreadCount) {
  MicroScene sc(test_util::gaussian_mirror_desc(64, 65e-6 / 8, 10e-6, 65e-6, 5));
  SimulateOptions o;
  o.lmax = 9;
  o.incident_directions = 1500;
  o.points = 5;
  SimulateStats st;
  o.threads = 1;
  const auto a = simulate(sc, o, &st).raw();
  EXPECT_GT(st.counters.escapes_bounded, st.counters.exits / 2);
  EXPECT_NEAR(st.counters.energy_out, double(st.counters.incident_rays), 1e-6 * 7500);
  for (int t : {2, 3}) {
    o.threads = t;
    EXPECT_EQ((simulate(sc, o).raw() - a).cwiseAbs().maxCoeff(), 0.0) << t;
  }
}

TEST(Simulate, QFallsAsOneOverSqrtN) {
  // A real traced scene: a Gaussian mirror surface (multiple bounces included).
  const MicroScene sc(test_util::gaussian_mirror_desc(64, 8e-6, 10e-6, 65e-6));
  std::vector<double> ln, lq;
  for (std::uint64_t n : {200, 2000, 20000}) {
    SimulateOptions o;
    o.lmax = 8;
    o.incident_directions = n;
    o.points = 1;
    SimulateStats st;
    simulate(sc, o, &st);
    ln.push_back(std::log(double(n)));
    lq.push_back(std::log(st.q));
  }
  const double slope = (lq[2] - lq[0]) / (ln[2] - ln[0]);
  EXPECT_NEAR(slope, -0.5, 0.1);
  EXPECT_NEAR((lq[1] - lq[0]) / (ln[1] - ln[0]), -0.5, 0.15);
}

TEST(Simulate, ParallelCylindersAreStronglyAnisotropic) {
  // Mirror cylinders along x on a black base: light along the axes stays near the mirror
  // direction; light across them is spread over the plane perpendicular to the axes.
  MicroSceneDesc d;
  d.width = d.height = 100e-6;
  d.materials.push_back(test_util::mirror_material());
  add_cylinders(d, 5e-6, 10, 5e-6, 0, 1, 0);
  MicroScene sc(std::move(d));
  const double half = 5 * kDeg;
  auto cone = [&](double phi_in, const std::vector<Vec>& dirs) {
    return cap_brdf(sc, dir(30, phi_in), dirs, half, 200000, TraceOptions{}, 1);
  };
  // Light in the xz plane (along the axes): the in-plane slice peaks at the mirror direction.
  const std::vector<Vec> along = {dir(30, 0), dir(0, 0), dir(60, 0)};
  const auto a = cone(180, along);
  // Light in the yz plane (across): the exits lie in the yz plane, spread.
  const std::vector<Vec> across = {dir(30, 90), dir(0, 0), dir(60, 90)};
  const auto c = cone(270, across);
  EXPECT_GT(a[0], 20 * std::max(a[1], a[2]));
  EXPECT_LT(c[0], 3 * std::min(c[1], c[2]));
  EXPECT_GT(c[1], 0.05);
  // And with the SH estimator: rho(wi, wo) for the mirror pair differs by a large factor
  // between the two orientations.
  SimulateOptions o;
  o.lmax = 10;
  o.incident_directions = 20000;
  o.points = 4;
  const ShBrdf b = ShBrdf::from_estimator(simulate(sc, o));
  // Towards the normal: on the great circle of the exits for light across the axes, 30 deg off
  // the cone of exits (v.x = 0.5) for light along them.
  const double r_across = b.eval(dir(30, 270), dir(0, 0), 550e-9);
  const double r_along = b.eval(dir(30, 180), dir(0, 0), 550e-9);
  EXPECT_GT(r_across, 5 * r_along);
}
