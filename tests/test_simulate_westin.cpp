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
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

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

// ---------------------------------------------------------------------------------------------
// W92 sections 5.3-5.4: velvet and cloth. Energy bookkeeping of the tracer (what leaves, what
// falls through, what the depth cap cuts) and the SH matrix against the direct in-plane estimate
// of the same scene (docs/westin.md, "Renders and checks of velvet and cloth").

namespace {

constexpr double kLambda = 550e-9;

// The velvet of examples/scenes/velvet.json; `clear` = non-absorbing fibres over a white
// Lambertian base (nothing is absorbed anywhere).
MicroScene velvet_scene(bool clear) {
  const std::string fibre = clear ? R"({"type": "dielectric", "eta": 1.5})"
                                  : R"({"type": "dielectric", "eta": 1.5, "absorption": "300um"})";
  const std::string base =
      clear ? R"({"type": "lambert", "albedo": 1})" : R"({"type": "absorber"})";
  const std::string text = R"({"name": "velvet", "tile": "500x500um",
    "materials": {"fibre": )" +
                           fibre + R"(, "base": )" + base + R"(},
    "objects": [
      {"type": "fibers", "count": 600, "radius": "6um", "length": "300um", "tilt": "10deg",
       "tilt_spread": "6deg", "tilt_azimuth": "0deg", "azimuth_spread": "180deg", "seed": 1,
       "material": "fibre"},
      {"type": "plane", "z": "0um", "material": "base"}]})";
  return MicroScene(parse_micro_scene(nlohmann::json::parse(text), ".", "velvet test scene"));
}

// The cloth of examples/scenes/cloth_threads.json + cloth.json: the thread surface simulated to
// `threads` (written to a temporary file the weave's material reads). `white`: threads and base
// white Lambertian instead (nothing absorbed).
MicroScene cloth_scene(const ShBrdf* threads, bool white = false) {
  const std::string dir = ::testing::TempDir();
  std::string thread = R"({"type": "lambert", "albedo": 1})";
  if (threads) {
    threads->save(dir + "/westin_test_threads.shbrdf");
    thread = R"({"type": "shbrdf", "file": "westin_test_threads.shbrdf"})";
  }
  const std::string base =
      white ? R"({"type": "lambert", "albedo": 1})" : R"({"type": "absorber"})";
  const std::string text = R"({"name": "cloth", "tile": "800x800um",
    "materials": {"thread": )" +
                           thread + R"(, "black": )" + base + R"(},
    "objects": [
      {"type": "weave", "pitch": "200um", "radius": "60um", "crimp": "60um", "segments": 12,
       "material": "thread"},
      {"type": "plane", "z": "-130um", "material": "black"}]})";
  return MicroScene(parse_micro_scene(nlohmann::json::parse(text), dir, "cloth test scene"));
}

ShBrdf thread_brdf(int lmax, std::uint64_t rays) {
  const std::string text = R"({"name": "cloth-threads", "tile": "100x100um",
    "materials": {"nylon": {"type": "mirror", "eta": 1.55}, "black": {"type": "absorber"}},
    "objects": [
      {"type": "cylinders", "radius": "5um", "count": 10, "z": "5um", "jitter": 0.1, "seed": 5,
       "material": "nylon"},
      {"type": "plane", "z": "0um", "material": "black"}]})";
  const MicroScene sc(parse_micro_scene(nlohmann::json::parse(text), ".", "threads test scene"));
  SimulateOptions o;
  o.lmax = lmax;
  o.incident_directions = rays / 16;
  return ShBrdf::from_estimator(simulate(sc, o));
}

struct Energy {
  double out, below, capped, lost;
  double sum() const { return out + below + capped + lost; }
};

Energy energy(const MicroScene& sc, std::uint64_t rays, int max_depth, std::uint64_t seed = 1) {
  SimulateOptions o;
  o.lmax = 4;
  o.incident_directions = rays / 16;
  o.trace.max_depth = max_depth;
  o.seed = seed;
  SimulateStats st;
  simulate(sc, o, &st);
  const double n = double(st.counters.incident_rays);
  const Energy e{st.counters.energy_out / n, st.counters.energy_down / n,
                 st.counters.energy_capped / n, st.counters.energy_lost / n};
  std::printf("depth cap %4d: out %.5f below %.5f capped %.5f lost %.5f, sum %.12f\n", max_depth,
              e.out, e.below, e.capped, e.lost, e.sum());
  return e;
}

// The SH matrix against the direct cone estimate at angles of incidence theta_i, in the plane of
// incidence (phi_i = 0), theta_r in [-70, 70] deg every 5 deg, 10 deg cones (wide: these BRDFs
// are low, 0.002-0.05 /sr, and the direct estimate needs the counts); the SH is averaged over the
// same cones. Compared in f = rho cos(theta_i) cos(theta_r), the quantity the matrix stores: the
// error of a truncated, Monte Carlo estimated expansion is spread evenly in f over all direction
// pairs, so it is measured relative to the largest f of all the direct curves (velvet and cloth
// reflect most at grazing incidence: the theta_i = 0 curve is 3 times lower than the 60 deg one).
// Also the directional albedo of the expansion (exact for the truncated matrix) against the
// traced fraction of energy that leaves.
struct ShVsDirect {
  double ti = 0, worst = 0, rms = 0, albedo_sh = 0, albedo_direct = 0;
};

std::vector<ShVsDirect> sh_vs_direct(const MicroScene& sc, const ShBrdf& sh,
                                     const std::vector<double>& ti_deg, bool isotropic,
                                     std::uint64_t rays) {
  std::vector<std::vector<double>> fd(ti_deg.size()), fs(ti_deg.size());
  std::vector<ShVsDirect> out(ti_deg.size());
  double scale = 0;
  for (std::size_t a = 0; a < ti_deg.size(); ++a) {
    GoniometerOptions g;
    g.theta_i_rad = {ti_deg[a] * kDeg};
    g.cone_half_angle_rad = 10 * kDeg;
    g.theta_r_min_deg = -70;
    g.theta_r_max_deg = 70;
    g.theta_r_step_deg = 5;
    g.rays = rays;
    g.seed = 77;
    g.isotropic = isotropic;
    const GoniometerCurve c = in_plane_goniometer(sc, g).at(0);
    const Vec wi(-std::sin(ti_deg[a] * kDeg), 0, std::cos(ti_deg[a] * kDeg));
    for (std::size_t k = 0; k < c.theta_r_deg.size(); ++k) {
      const double t = c.theta_r_deg[k] * kDeg;
      const Vec wo(std::sin(t), 0, std::cos(t));
      const double rho_sh =
          cone_average([&](const Vec& w) { return sh.cosine_weighted(wi, w) / (wi.z() * w.z()); },
                       wo, g.cone_half_angle_rad, Vec(0, 1, 0));
      fd[a].push_back(c.simulated[k] * wi.z() * wo.z());
      fs[a].push_back(rho_sh * wi.z() * wo.z());
      scale = std::max(scale, fd[a].back());
    }
    out[a].ti = ti_deg[a];
    out[a].albedo_sh = sh.albedo(wi);
    out[a].albedo_direct = c.albedo;
  }
  for (std::size_t a = 0; a < ti_deg.size(); ++a) {
    auto& r = out[a];
    for (std::size_t k = 0; k < fd[a].size(); ++k) {
      const double d = std::abs(fs[a][k] - fd[a][k]) / scale;
      r.worst = std::max(r.worst, d);
      r.rms += d * d;
    }
    r.rms = std::sqrt(r.rms / double(fd[a].size()));
    std::printf(
        "theta_i %2.0f: f(SH) - f(direct) relative to the largest f %.4g: worst %.3f, rms %.3f "
        "(this curve's peak %.4g); albedo SH %.5f, traced %.5f\n",
        r.ti, scale, r.worst, r.rms, *std::max_element(fd[a].begin(), fd[a].end()), r.albedo_sh,
        r.albedo_direct);
  }
  return out;
}

}  // namespace

TEST(WestinVelvet, EnergyBalanceWithTheDepthCap) {
  // Non-absorbing fibres over a white base: nothing is absorbed, so what leaves, what falls
  // through, what the depth cap cuts and what is lost add up to the incident energy exactly (the
  // weights stay 1, Russian roulette never fires). Light is trapped for long: the cap cuts 45 %
  // at depth 100 and 96 % at depth 10, and the balance still closes.
  const MicroScene clear = velvet_scene(true);
  const Energy d10 = energy(clear, 4000, 10), d100 = energy(clear, 4000, 100);
  EXPECT_NEAR(d10.sum(), 1.0, 1e-9);
  EXPECT_NEAR(d100.sum(), 1.0, 1e-9);
  EXPECT_GT(d10.capped, d100.capped + 0.2);
  EXPECT_GT(d100.capped, 0.1);
  // The velvet of W92 (absorbing fibres, black base). Raising the cap from 100 to 1000 events
  // (same seed: the same paths up to the cap) can only return part of what the cap cut at 100:
  // 0 <= out(1000) - out(100) <= capped(100), and the cut at 1000 is far smaller.
  const MicroScene velvet = velvet_scene(false);
  const Energy v100 = energy(velvet, 20000, 100), v1000 = energy(velvet, 20000, 1000);
  EXPECT_GT(v100.capped, 0.01);  // 4.7 % with 2 M rays (docs/westin.md)
  EXPECT_LT(v100.sum(), 1.0);
  EXPECT_GE(v1000.out - v100.out, -0.002);
  EXPECT_LE(v1000.out - v100.out, v100.capped + 0.002);
  EXPECT_LT(v1000.capped, 0.2 * v100.capped);
  std::printf(
      "velvet: absorbed %.4f (cap 100), %.4f (cap 1000); the cap at 100 cut %.4f, of "
      "which %.4f left the surface with the cap at 1000\n",
      1 - v100.sum(), 1 - v1000.sum(), v100.capped, v1000.out - v100.out);
}

TEST(WestinCloth, EnergyBalance) {
  // The weave with white Lambertian threads and base: everything comes out (or is cut by the
  // cap); with the simulated nylon-thread BRDF the matrix's own albedo (< 0.4 at every angle)
  // lets most of the energy be absorbed, and nothing falls through the closed base.
  const MicroScene white = cloth_scene(nullptr, true);
  const Energy w = energy(white, 8000, 100);
  EXPECT_NEAR(w.sum(), 1.0, 1e-9);
  EXPECT_NEAR(w.out + w.capped, 1.0, 1e-9);
  const ShBrdf threads = thread_brdf(8, 40000);
  const MicroScene cloth = cloth_scene(&threads);
  const Energy c = energy(cloth, 8000, 100);
  EXPECT_EQ(c.below, 0.0);
  EXPECT_LT(c.capped, 1e-3);
  EXPECT_GT(c.out, 0.02);
  EXPECT_LT(c.out, 0.2);
}

TEST(WestinVelvet, SlowShMatrixMatchesTheDirectInPlaneEstimate) {
  // lmax 12, 10^6 rays (as `microbrdf simulate velvet.json --lmax 12`), averaged over rotations
  // about n (velvet is statistically isotropic); the direct estimate with the plane of incidence
  // at random azimuths, 10^6 rays per angle (docs/westin.md, "Checks of velvet and cloth").
  const MicroScene sc = velvet_scene(false);
  SimulateOptions o;
  o.lmax = 12;
  o.incident_directions = 1000000 / 16;
  const ShBrdf sh = ShBrdf::from_estimator(simulate(sc, o)).isotropic_average();
  // Measured (rms / worst of |f(SH) - f(direct)| over the largest f, albedo SH / traced):
  // 0.076 / 0.188 / 0.89 at theta_i = 0, 0.033 / 0.093 / 1.00 at 30, 0.031 / 0.065 / 1.00 at 60.
  // Two independent 10^6-ray matrices (seeds 1, 2) differ from each other by 0.074 / 0.198,
  // 0.042 / 0.105, 0.031 / 0.062: the difference is the matrix's Monte Carlo noise, largest at
  // the pole (every m = 0 term peaks there). Tolerances 0.12 / 0.3, albedo 15 % at 0 and 5 %.
  for (const ShVsDirect& r : sh_vs_direct(sc, sh, {0, 30, 60}, true, 1000000)) {
    EXPECT_LT(r.rms, 0.12) << r.ti;
    EXPECT_LT(r.worst, 0.3) << r.ti;
    EXPECT_NEAR(r.albedo_sh / r.albedo_direct, 1.0, r.ti == 0 ? 0.15 : 0.05) << r.ti;
  }
}

TEST(WestinCloth, SlowShMatrixMatchesTheDirectInPlaneEstimate) {
  // Threads at lmax 12 (2 x 10^6 rays), the weave at lmax 12 (10^6 rays), phi_i = 0 (the plane
  // of incidence along the warp), 10^6 rays per angle for the direct estimate.
  const ShBrdf threads = thread_brdf(12, 2000000);
  const MicroScene sc = cloth_scene(&threads);
  SimulateOptions o;
  o.lmax = 12;
  o.incident_directions = 1000000 / 16;
  const ShBrdf sh = ShBrdf::from_estimator(simulate(sc, o));
  // Measured: rms / worst 0.097 / 0.222, 0.082 / 0.183, 0.064 / 0.149 at theta_i = 0, 30, 60;
  // albedo SH / traced 0.978, 0.986, 0.970. Same tolerances as the velvet.
  for (const ShVsDirect& r : sh_vs_direct(sc, sh, {0, 30, 60}, false, 1000000)) {
    EXPECT_LT(r.rms, 0.12) << r.ti;
    EXPECT_LT(r.worst, 0.3) << r.ti;
    EXPECT_NEAR(r.albedo_sh / r.albedo_direct, 1.0, r.ti == 0 ? 0.15 : 0.05) << r.ti;
  }
}
