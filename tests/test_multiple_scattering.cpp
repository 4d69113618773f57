// Multiple scattering (microfacet random walk, include/microbrdf/multiple_scattering.hpp).
//
// The references here are written independently of the code under test: directional albedo by
// product quadrature of eval() (the single-scattering part on a half-vector chart stretched
// like the lobe, the multiple-scattering part on a Gauss-Legendre x midpoint grid of the
// hemisphere), the sampler against pdf() by Pearson's chi-square.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <vector>

#include "microbrdf/brdf_spec.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/microscene.hpp"
#include "microbrdf/multiple_scattering.hpp"
#include "microbrdf/quadrature.hpp"
#include "microbrdf/tabulated_distribution.hpp"
#include "test_microfacet_common.hpp"

using namespace microbrdf;
using mtest::direction;
using mtest::kPi;

namespace {

struct Case {
  std::string model;
  double ax, ay;
};

std::shared_ptr<const MicrofacetDistribution> make(const Case& c) {
  if (c.model == "tabulated") {
    // A Beckmann table (the measured-NDF path): 257^2 nodes resolve alpha >= 0.1.
    BeckmannDistribution b(c.ax, c.ay, 0);
    return std::make_shared<TabulatedDistribution>(tabulate(b, "beckmann", 257));
  }
  if (c.model == "ellipsoid")
    return std::make_shared<EllipsoidDistribution>(EllipsoidParams{c.ax, c.ay, 0, 0, 0});
  NdfSpec s;
  s.model = c.model;
  s.alpha_x = c.ax;
  s.alpha_y = c.ay;
  return make_distribution(s);
}

MultipleScatteringOptions small_options() {
  MultipleScatteringOptions o;
  o.eval_walks = 4;
  o.table.theta_nodes = 6;
  o.table.phi_nodes = 12;
  o.table.walks = 16;
  return o;
}

// Albedo of f = single + multiple by quadrature: the single part over half vectors h (dwo =
// 4 (wi.h) dw_h) on a chart stretched like the lobe, the multiple part over wo on the plain
// hemisphere (its lobe is wide).
struct Albedo {
  double single = 0, multiple = 0, multiple_se = 0;
  double total() const { return single + multiple; }
};
Albedo albedo_quadrature(const MultipleScatteringBrdf& b, const Case& c, const Vec3& wi, int walks,
                         std::uint64_t seed) {
  Albedo a;
  const mtest::Chart lobe(mtest::lobe_stretch(c.ax, c.ay, 0));
  a.single = lobe.integrate(
      [&](const Vec3& h) {
        const double ih = wi.dot(h);
        if (ih <= 0) return 0.0;
        const Vec3 wo = 2 * ih * h - wi;
        if (wo.z() <= 0) return 0.0;
        return b.eval_single(wi, wo, 550e-9) * wo.z() * 4 * ih;
      },
      192, 192);
  // The multiple-scattering lobe hugs the horizon at grazing incidence and small alpha:
  // Gauss-Legendre in s with cos(theta_o) = s^2 puts more nodes there; midpoint in phi.
  std::vector<double> x, w;
  // Each walk's next-event estimates form a lobe as narrow as the NDF: a finer grid for alpha
  // 0.1 (32 nodes under-resolve its lobe at the horizon by half at theta_i = 80 deg).
  const int nu = std::min(c.ax, c.ay) < 0.3 ? 64 : 32;
  gauss_legendre(nu, x, w);
  const int nphi = 3 * nu;
  const double phi_f = std::atan2(-wi.y(), -wi.x());
  std::vector<Vec3> nodes;
  std::vector<double> weights, lam;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double s = 0.5 * (x[i] + 1), u = s * s, du = s * w[i];
    const double st = std::sqrt(std::max(0.0, 1 - u * u));
    for (int j = 0; j < nphi; ++j) {
      const double phi = phi_f + 2 * kPi * (j + 0.5) / nphi - kPi, dphi = 2 * kPi / nphi;
      nodes.emplace_back(st * std::cos(phi), st * std::sin(phi), u);
      weights.push_back(du * dphi);
      lam.push_back(b.walk().lambda(nodes.back()));
    }
  }
  // The same walks estimate f cos(theta_o) at every node (eval_multiple's estimator, with common
  // walks across the nodes): the quadrature of their mean is the quadrature of the expectation.
  // Per walk: its estimate of the energy of orders >= 2 (the quadrature of its next-event
  // estimates); the mean over walks and its standard error.
  std::vector<double> out(nodes.size());
  WalkRng rng(seed);
  double sum = 0, sum2 = 0;
  for (int k = 0; k < walks; ++k) {
    std::fill(out.begin(), out.end(), 0.0);
    b.walk().eval_cos_many(wi, nodes.data(), lam.data(), nodes.size(), rng, nullptr, 550e-9,
                           out.data(), 2);
    double e = 0;
    for (std::size_t j = 0; j < nodes.size(); ++j) e += out[j] * weights[j];
    sum += e;
    sum2 += e * e;
  }
  a.multiple = sum / walks;
  a.multiple_se = std::sqrt(std::max(0.0, sum2 / walks - a.multiple * a.multiple) / (walks - 1));
  return a;
}

int walks_env() {
  const char* e = std::getenv("MS_WALKS");
  return e ? std::atoi(e) : 1024;
}

}  // namespace

// White furnace: F = 1 conserves energy, so single + multiple scattering reflects everything
// (less what walks still on the surface after max_order hits carry). The multiple part is a
// Monte Carlo mean: the bounds allow 3 standard errors (about 0.015 with 1024 walks; the
// figures in docs/multiple_scattering.md come from MS_WALKS=16384).
void furnace(const std::vector<Case>& cases, const std::vector<double>& thetas) {
  const auto one = std::make_shared<PerfectMirrorFresnel>();
  for (const Case& c : cases) {
    const MultipleScatteringBrdf b(make(c), one, small_options());
    for (const double t : thetas) {
      const Vec3 wi = direction(t, 30);
      const Albedo a = albedo_quadrature(b, c, wi, walks_env(),
                                         static_cast<std::uint64_t>(t + 1000 * c.ax + 1e4 * c.ay));
      std::printf(
          "furnace %-9s %.1f x %.1f theta_i %2.0f: single %.4f + multiple %.4f = %.4f (se %.4f)\n",
          c.model.c_str(), c.ax, c.ay, t, a.single, a.multiple, a.total(), a.multiple_se);
      EXPECT_GE(a.total(), 0.99 - 3 * a.multiple_se)
          << c.model << " " << c.ax << "x" << c.ay << " at " << t;
      EXPECT_LE(a.total(), 1.01 + 3 * a.multiple_se)
          << c.model << " " << c.ax << "x" << c.ay << " at " << t;
      // Single scattering alone loses energy wherever the multiple part is resolved.
      if (a.multiple > 5 * a.multiple_se) {
        EXPECT_LT(a.single, 1 - 0.5 * a.multiple);
      }
    }
  }
}

const std::vector<Case> kFurnaceCases = {
    {"beckmann", 0.1, 0.1},  {"beckmann", 0.5, 0.5},  {"beckmann", 1.0, 1.0},
    {"beckmann", 0.1, 0.8},  {"ggx", 0.1, 0.1},       {"ggx", 0.5, 0.5},
    {"ggx", 1.0, 1.0},       {"ggx", 0.1, 0.8},       {"ellipsoid", 0.1, 0.1},
    {"ellipsoid", 0.5, 0.5}, {"ellipsoid", 1.0, 1.0}, {"ellipsoid", 0.1, 0.8},
    {"tabulated", 0.1, 0.1}, {"tabulated", 0.5, 0.5}, {"tabulated", 1.0, 1.0},
    {"tabulated", 0.1, 0.8}};

TEST(MultipleScattering, WhiteFurnaceEveryNdf) { furnace(kFurnaceCases, {0.0, 60.0, 80.0}); }

// The roughest cases alone (alpha = 1: the largest multiple part and the largest spread between
// walks), for a run with many walks (MS_WALKS=65536 gives a standard error near 0.0025).
TEST(MultipleScattering, SlowWhiteFurnaceRoughest) {
  furnace({{"beckmann", 1.0, 1.0}, {"ggx", 1.0, 1.0}, {"tabulated", 1.0, 1.0}},
          {0.0, 30.0, 45.0, 60.0, 70.0, 75.0, 80.0});
}

TEST(MultipleScattering, SlowWhiteFurnaceEveryAngle) {
  furnace(kFurnaceCases, {0.0, 30.0, 45.0, 60.0, 70.0, 75.0, 80.0});
}

// A conductor reflects less than the white surface, and multiple scattering adds to it.
TEST(MultipleScattering, ConductorBelowWhite) {
  const auto d = std::make_shared<GgxDistribution>(0.6);
  const auto cu = std::make_shared<ConductorFresnel>(metal("Cu"));
  const MultipleScatteringBrdf b(d, cu, small_options());
  const Vec3 wi = direction(45, 0), wo = direction(30, 150);
  const double single = b.eval_single(wi, wo, 550e-9), multi = b.eval_multiple(wi, wo, 550e-9, 256);
  EXPECT_GT(multi, 0);
  EXPECT_DOUBLE_EQ(b.eval(wi, wo, 550e-9), single + b.eval_multiple(wi, wo, 550e-9, 4));
  // Two hits at least: the multiple part of copper at 550 nm is below F(0)^2 times the white one
  // (F < F(0) = 0.6 ... 0.65 at every angle below 70 deg, the walk's typical angles).
  const MultipleScatteringBrdf w(d, std::make_shared<PerfectMirrorFresnel>(), small_options());
  const double white = w.eval_multiple(wi, wo, 550e-9, 256);
  EXPECT_LT(multi, 0.7 * white);
  EXPECT_GT(multi, 0.2 * white);
}

// The renderer asks for every wavelength of a path at once: eval_spectral takes the walks once,
// with each wavelength's Fresnel factors, and must give eval()'s numbers exactly (copper, whose
// F varies with the wavelength; a tabulated NDF and GGX; several direction pairs, including
// grazing ones whose walks run long).
TEST(MultipleScattering, SpectralEvalEqualsEvalPerWavelength) {
  const auto cu = std::make_shared<ConductorFresnel>(metal("Cu"));
  const double lambdas[] = {380e-9, 455e-9, 530e-9, 605e-9, 680e-9, 755e-9};
  for (const Case& c : {Case{"tabulated", 0.5, 0.3}, Case{"ggx", 0.8, 0.8}}) {
    const MultipleScatteringBrdf b(make(c), cu, small_options());
    for (const auto& [ti, pi, to, po] : {std::array<double, 4>{45, 0, 30, 150},
                                         {80, 20, 85, 200},
                                         {10, 90, 60, 10},
                                         {70, 0, 70, 180}}) {
      const Vec3 wi = direction(ti, pi), wo = direction(to, po);
      double f[6];
      b.eval_spectral(wi, wo, lambdas, 6, f);
      for (int k = 0; k < 6; ++k) EXPECT_EQ(f[k], b.eval(wi, wo, lambdas[k])) << c.model << k;
      EXPECT_NE(f[0], f[5]);  // copper's F does differ across the spectrum
    }
  }
}

// Deterministic: the same call gives the same number; the table does not depend on threads.
TEST(MultipleScattering, DeterministicAndThreadIndependent) {
  const auto d = std::make_shared<BeckmannDistribution>(0.3, 0.7, 0.4);
  const auto one = std::make_shared<PerfectMirrorFresnel>();
  const MultipleScatteringBrdf b(d, one, small_options());
  const Vec3 wi = direction(50, 10), wo = direction(20, 200);
  EXPECT_EQ(b.eval(wi, wo, 500e-9), b.eval(wi, wo, 500e-9));
  // The wavelength is not in the seed: with F = 1 every wavelength gives the same number.
  EXPECT_EQ(b.eval(wi, wo, 500e-9), b.eval(wi, wo, 700e-9));
  MsTableOptions o;
  o.theta_nodes = 5;
  o.phi_nodes = 8;
  o.walks = 32;
  o.threads = 1;
  const MsTable t1 = tabulate_multiple_scattering(b.walk(), nullptr, 550e-9, o);
  o.threads = 2;
  const MsTable t2 = tabulate_multiple_scattering(b.walk(), nullptr, 550e-9, o);
  for (std::size_t i = 0; i < t1.nodes(); ++i) {
    EXPECT_EQ(t1.node_energy(i), t2.node_energy(i));
    for (std::size_t j = 0; j < t1.nodes(); ++j) ASSERT_EQ(t1.node(i, j), t2.node(i, j));
  }
}

// Reciprocity of the tabulated form: f_ms(a, b) = f_ms(b, a) up to its Monte Carlo error. The
// error is measured by a second table with another seed: the asymmetry must be of that size.
TEST(MultipleScattering, TableReciprocalWithinItsNoise) {
  const auto d = std::make_shared<GgxDistribution>(0.3, 0.7, 0.5);  // no symmetry used
  const MicrofacetRandomWalk walk(d);
  MsTableOptions o;
  o.theta_nodes = 6;
  o.phi_nodes = 12;
  o.walks = 1024;
  const MsTable a = tabulate_multiple_scattering(walk, nullptr, 550e-9, o);
  o.seed = 7;
  const MsTable b = tabulate_multiple_scattering(walk, nullptr, 550e-9, o);
  double peak = 0;
  for (std::size_t i = 0; i < a.nodes(); ++i)
    for (std::size_t j = 0; j < a.nodes(); ++j) peak = std::max(peak, a.node(i, j));
  std::vector<double> asym, noise;
  for (std::size_t i = 0; i < a.nodes(); ++i)
    for (std::size_t j = i + 1; j < a.nodes(); ++j) {
      const double x = a.node(i, j), y = a.node(j, i);
      if (x + y < 0.02 * peak) continue;
      asym.push_back(2 * std::abs(x - y) / (x + y));
      noise.push_back(2 * std::abs(x - b.node(i, j)) / (x + b.node(i, j)));
    }
  ASSERT_GT(asym.size(), 500u);
  auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  const double ma = median(asym), mn = median(noise);
  std::printf("reciprocity: median |f(a,b) - f(b,a)| / mean %.4f; seed-to-seed %.4f (%zu pairs)\n",
              ma, mn, asym.size());
  EXPECT_LT(ma, 1.3 * mn);
  EXPECT_LT(ma, 0.1);
}

// sample() against pdf(): Pearson's chi-square on 16 x 32 equal-area bins.
TEST(MultipleScattering, SampleMatchesPdfChiSquare) {
  for (const Case& c : {Case{"ggx", 0.8, 0.8}, Case{"beckmann", 0.2, 0.9}}) {
    MultipleScatteringOptions o = small_options();
    o.table.theta_nodes = 12;
    o.table.phi_nodes = 24;
    o.table.walks = 256;
    const MultipleScatteringBrdf b(make(c), std::make_shared<PerfectMirrorFresnel>(), o);
    for (const double t : {30.0, 70.0}) {
      const Vec3 wi = direction(t, 20);
      std::vector<Vec3> samples;
      std::mt19937_64 g(42);
      std::uniform_real_distribution<double> u(0, 1);
      const int n = 40000;
      for (int k = 0; k < n; ++k)
        if (const auto s = b.sample(wi, u(g), u(g), 550e-9)) {
          samples.push_back(s->wo);
          EXPECT_NEAR(s->weight, b.eval(wi, s->wo, 550e-9) * s->wo.z() / s->pdf, 1e-12 * s->weight);
          EXPECT_NEAR(s->pdf, b.pdf(wi, s->wo), 1e-12 * s->pdf);
        }
      // pdf() is the density per attempt; attempts that reflect below the horizon return
      // nothing: their share must be 1 - the integral of pdf() over the hemisphere (binomial
      // error), and the returned samples follow pdf() / that integral.
      const mtest::Chart hemi(Eigen::Matrix3d::Identity());
      const double mass = hemi.integrate([&](const Vec3& wo) { return b.pdf(wi, wo); }, 128, 128);
      const double share = static_cast<double>(samples.size()) / n;
      EXPECT_NEAR(share, mass, 4 * std::sqrt(mass * (1 - mass) / n) + 1e-3);
      const auto r = mtest::chi_square(
          hemi, samples, [&](const Vec3& wo) { return b.pdf(wi, wo) / mass; }, 0.01 / 4, 16, 32);
      std::printf(
          "chi-square %s %.1f x %.1f theta_i %.0f: %.1f (dof %d, critical %.1f), returned "
          "%.4f, pdf integral %.4f\n",
          c.model.c_str(), c.ax, c.ay, t, r.chi2, r.dof, r.critical, share, mass);
      EXPECT_LT(r.chi2, r.critical);
    }
  }
}

// The vocabulary: JSON / CLI keys build the multiple-scattering BRDF, off by default.
TEST(MultipleScattering, SpecKeys) {
  MaterialSpec cu = MaterialSpec::named_metal("Cu");
  const auto plain = make_brdf(parse_brdf({{"model", "ggx"}, {"alpha", 0.4}}), cu);
  EXPECT_NE(dynamic_cast<const MicrofacetBrdf*>(plain.get()), nullptr);
  const auto ms = make_brdf(
      parse_brdf(
          {{"model", "ggx"}, {"alpha", 0.4}, {"multiple_scattering", true}, {"ms_walks", 8}}),
      cu);
  const auto* m = dynamic_cast<const MultipleScatteringBrdf*>(ms.get());
  ASSERT_NE(m, nullptr);
  EXPECT_NE(m->describe().find("8 walks per eval"), std::string::npos);
  EXPECT_THROW(parse_brdf({{"sun", 3}, {"multiple_scattering", true}}), InputError);
  EXPECT_THROW(parse_brdf({{"model", "ggx"}, {"alpha", 0.4}, {"ms_walks", 8}}), InputError);
  EXPECT_THROW(
      parse_brdf(
          {{"model", "ggx"}, {"alpha", 0.4}, {"multiple_scattering", true}, {"separable_g", true}}),
      InputError);
}

// The micro-scene JSON takes the key too (a microfacet material of `simulate`).
TEST(MultipleScattering, MicroSceneMaterial) {
  const nlohmann::json j = nlohmann::json::parse(R"({
    "tile": "10x10um",
    "materials": {
      "rough": {"type": "microfacet", "model": "ggx", "alpha": 0.5, "metal": "Cu",
                "multiple_scattering": true, "ms_walks": 2},
      "plain": {"type": "microfacet", "model": "ggx", "alpha": 0.5, "metal": "Cu"}
    },
    "objects": [{"type": "plane", "z": "0um", "material": "rough"}]
  })");
  const MicroSceneDesc d = parse_micro_scene(j, ".", "test.json");
  int ms = 0, plain = 0;
  for (const auto& m : d.materials) {
    if (dynamic_cast<const MultipleScatteringBrdf*>(m.brdf.get())) ++ms;
    if (dynamic_cast<const MicrofacetBrdf*>(m.brdf.get())) ++plain;
  }
  EXPECT_EQ(ms, 1);
  EXPECT_EQ(plain, 1);
}
