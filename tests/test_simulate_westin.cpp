// W92 section 5.1 / Fig. 6: a Gaussian mirror surface (sigma = 10 um, tau = 65 um, F = 1) traced
// on Embree against He et al. 1991 in its geometric-optics limit and Beckmann + Smith
// (docs/theory.md §6.7). The direct in-plane estimate (cones around in-plane directions, plane of
// incidence turned to all azimuths) checks the ray tracer by itself; the SH pipeline is compared in
// the slow test with the projection of the reference on the same basis.
//
// He and Smith are single-scattering models. The ray tracer follows every bounce; restricted to
// one bounce (max_depth = 1) it matches Smith within 4 % everywhere and He within 6 % for
// theta_i <= 60 deg. At theta_i = 75 deg He's shadowing (numerator 1 - erfc(a)/2, docs/theory.md
// §6.7) is 11 % below Smith's per direction, and He is 20 % below the simulation. With all bounces
// the forward lobe at theta_i >= 60 deg gains up to 20 % near grazing exits (docs/westin.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "microbrdf/generate.hpp"
#include "microbrdf/goniometer.hpp"
#include "microbrdf/microfacet.hpp"
#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/sh_brdf.hpp"
#include "microbrdf/simulate.hpp"
#include "microscene_test_util.hpp"

using namespace microbrdf;
using Vec = Eigen::Vector3d;

namespace {

constexpr double kDeg = M_PI / 180;
constexpr double kSigma = 10e-6, kTau = 65e-6;

MicroScene westin_scene(std::size_t n, std::uint64_t seed) {
  return MicroScene(test_util::gaussian_mirror_desc(n, kTau / 8, kSigma, kTau, seed));
}

struct Comparison {
  double worst_he = 0, worst_smith = 0, albedo = 0, below = 0;
};

// The virtual goniometer of `microbrdf simulate --in-plane` (in_plane_goniometer, with its
// cone-averaged references), theta_r in [-65, 70] deg: the worst relative deviation where a
// reference exceeds `threshold` x its peak.
Comparison compare(const MicroScene& sc, double theta_i_deg, std::uint64_t rays, double half,
                   double threshold, int max_depth) {
  GoniometerOptions g;
  g.theta_i_rad = {theta_i_deg * kDeg};
  g.cone_half_angle_rad = half;
  g.theta_r_min_deg = -65;
  g.theta_r_max_deg = 70;
  g.theta_r_step_deg = 5;
  g.rays = rays;
  g.trace.max_depth = max_depth;
  g.seed = 1234;
  g.isotropic = true;
  g.he_sigma_m = kSigma;
  g.he_tau_m = kTau;
  const GoniometerCurve c = in_plane_goniometer(sc, g).at(0);
  const auto& sim = c.simulated;
  const auto& he = c.he1991;
  const auto& sm = c.beckmann_smith;
  const double peak_he = *std::max_element(he.begin(), he.end());
  const double peak_sm = *std::max_element(sm.begin(), sm.end());
  Comparison out;
  for (std::size_t k = 0; k < sim.size(); ++k) {
    if (he[k] > threshold * peak_he)
      out.worst_he = std::max(out.worst_he, std::abs(sim[k] / he[k] - 1));
    if (sm[k] > threshold * peak_sm)
      out.worst_smith = std::max(out.worst_smith, std::abs(sim[k] / sm[k] - 1));
  }
  out.albedo = c.albedo;
  out.below = c.energy_below;
  std::printf("theta_i %2.0f depth %3d: albedo %.5f, worst deviation from He %.3f, Smith %.3f\n",
              theta_i_deg, max_depth, out.albedo, out.worst_he, out.worst_smith);
  return out;
}

}  // namespace

TEST(WestinFig6, DirectSingleScatterMatchesSmith) {
  // Small version: 256^2 samples (32 tau across), two angles, the lobe above 20 % of its peak.
  const MicroScene sc = westin_scene(256, 2);
  for (double ti : {0.0, 45.0}) {
    const Comparison c = compare(sc, ti, 300000, 5 * kDeg, 0.2, 1);
    EXPECT_LT(c.worst_smith, 0.10) << ti;
    EXPECT_LT(c.worst_he, 0.10) << ti;
  }
}

TEST(WestinFig6, SlowDirectEstimateMatchesHeAndSmith) {
  // W92's size: 1024^2 samples at tau/8 = an 8.3 mm tile (W92: 8 x 8 mm), 2.1 M triangles.
  const MicroScene sc = westin_scene(1024, 1);
  for (double ti : {0.0, 30.0, 45.0, 60.0, 75.0}) {
    const Comparison one = compare(sc, ti, 2000000, 4 * kDeg, 0.05, 1);
    EXPECT_LT(one.worst_smith, 0.10) << ti;
    if (ti <= 60) {
      EXPECT_LT(one.worst_he, 0.10) << ti;
    }
    // Multiple bounces: a closed mirror surface with F = 1 returns everything.
    const Comparison all = compare(sc, ti, 2000000, 4 * kDeg, 0.05, 100);
    EXPECT_NEAR(all.albedo, 1.0, 1e-5) << ti;
    EXPECT_LT(all.below, 1e-5) << ti;
    if (ti <= 30) {
      EXPECT_LT(all.worst_smith, 0.10) << ti;
    }
  }
}

TEST(WestinFig6, SlowShMatrixMatchesTheProjectedReference) {
  // The full pipeline at l_max = 15 on W92's polygon count (512^2 samples, 524 288 triangles):
  // the symmetrised SH matrix of the single-scattering simulation against the Beckmann-Smith
  // BRDF projected on the same basis (so the truncation is the same on both sides), in the plane
  // of incidence. (With all bounces, the grazing multiple-scattering excess rings through the
  // truncated expansion and shifts the low wings at theta_i = 0 by ~20 %: docs/westin.md.)
  const MicroScene sc = westin_scene(512, 3);
  SimulateOptions o;
  o.lmax = 15;
  o.incident_directions = 250000;
  o.points = 16;
  o.trace.max_depth = 1;
  SimulateStats st;
  const ShBrdf sim = ShBrdf::from_estimator(simulate(sc, o, &st));
  MicrofacetBrdf smith(std::make_shared<BeckmannDistribution>(2 * kSigma / kTau),
                       std::make_shared<PerfectMirrorFresnel>());
  const ShBrdf ref = ShBrdf::project(smith, 15, 550e-9, 64);
  std::printf("Q = %.3g after %.3g rays\n", st.q, double(st.counters.incident_rays));
  for (double ti : {0.0, 30.0, 45.0}) {
    const Vec wi(-std::sin(ti * kDeg), 0, std::cos(ti * kDeg));
    std::vector<double> a, b;
    for (double t = -65; t <= 70 + 1e-9; t += 5) {
      const Vec wo(std::sin(t * kDeg), 0, std::cos(t * kDeg));
      a.push_back(sim.eval(wi, wo, 550e-9));
      b.push_back(ref.eval(wi, wo, 550e-9));
    }
    const double peak = *std::max_element(b.begin(), b.end());
    double worst = 0;
    for (std::size_t k = 0; k < a.size(); ++k)
      // Above 20 % of the peak: the SH estimate's absolute error is about uniform in f = rho cos
      // cos (here ~5e-3 after 4e6 rays, i.e. ~0.014 in rho at theta_r = 65 deg), so the low wings
      // need far more rays for 10 % (W92 section 5.1 makes the same observation).
      if (b[k] > 0.2 * peak) {
        worst = std::max(worst, std::abs(a[k] / b[k] - 1));
      }
    std::printf("theta_i %2.0f: SH(simulation) vs SH(Beckmann-Smith): worst %.3f\n", ti, worst);
    EXPECT_LT(worst, 0.10) << ti;
  }
}
