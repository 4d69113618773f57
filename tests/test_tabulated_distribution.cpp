// A TabulatedNdf as a microfacet distribution: projected-area G1 against the analytic Smith G1,
// weak white furnace, BRDF reciprocity, sampling pdf, agreement with the analytic BRDF.
#include <cmath>
#include <cstdio>
#include <random>
#include <utility>
#include <vector>

#include "microbrdf/brdf.hpp"
#include "microbrdf/brdf_albedo.hpp"
#include "microbrdf/brdf_slice.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/svbrdf.hpp"
#include "microbrdf/tabulated_distribution.hpp"
#include "models/tabulated_distribution_vn.hpp"
#include "render/material.hpp"
#include "test_microfacet_common.hpp"

using namespace microbrdf;
using mtest::direction;

namespace {

// The analytic model tabulated on an N x N disk and normalised (tabulate()), wrapped.
struct Pair {
  std::shared_ptr<MicrofacetDistribution> analytic;
  std::shared_ptr<TabulatedDistribution> table;
};

// 128^2 slope bins instead of the default 256^2 keep every test process under a second (each
// ctest case builds its tables); the default is checked in G1MatchesAnalyticSmith.
Pair make_pair(const NdfSpec& s, std::size_t n = 513, std::size_t bins = 128,
               TabulatedSampling sampling = TabulatedSampling::Visible) {
  auto a = make_distribution(s);
  TabulatedDistributionOptions o;
  o.sigma_bins = bins;
  o.sampling = sampling;
  return {a, std::make_shared<TabulatedDistribution>(tabulate(*a, s.model, n), o)};
}

const Pair& beckmann03() {
  static const Pair p = make_pair(NdfSpec{"beckmann", 0.3, 0.3, 0, 0, 0, 0, {}});
  return p;
}
const Pair& ggx03() {
  static const Pair p = make_pair(NdfSpec{"ggx", 0.3, 0.3, 0, 0, 0, 0, {}});
  return p;
}
const Pair& beckmann_aniso() {
  static const Pair p = make_pair(NdfSpec{"beckmann", 0.4, 0.2, 0.5, 0, 0, 0, {}});
  return p;
}
// The narrow brushed-like lobe of the sampling tests (alpha 0.02 x 0.3, axis at 0.5 rad), with
// the visible-normal sampler and with the plain D(m)(m.n) sampler on the same table.
const Pair& narrow() {
  static const Pair p = make_pair(NdfSpec{"beckmann", 0.02, 0.3, 0.5, 0, 0, 0, {}});
  return p;
}
const Pair& narrow_ndf() {
  static const Pair p =
      make_pair(NdfSpec{"beckmann", 0.02, 0.3, 0.5, 0, 0, 0, {}}, 513, 128, TabulatedSampling::Ndf);
  return p;
}
const Pair& beckmann03_ndf() {
  static const Pair p =
      make_pair(NdfSpec{"beckmann", 0.3, 0.3, 0, 0, 0, 0, {}}, 513, 128, TabulatedSampling::Ndf);
  return p;
}

// Mean and variance of the per-sample weight of MicrofacetBrdf::sample (0 when absorbed) over
// n independent uniform pairs: the directional albedo estimator with the BRDF's own sampler.
struct WeightStats {
  double mean = 0, var = 0;
};
WeightStats weight_stats(const Brdf& b, const Vec3& wi, int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  double s = 0, s2 = 0;
  for (int k = 0; k < n; ++k) {
    auto smp = b.sample(wi, u(rng), u(rng), 550e-9);
    const double w = smp ? smp->weight : 0.0;
    s += w;
    s2 += w * w;
  }
  WeightStats r;
  r.mean = s / n;
  r.var = std::max(0.0, s2 / n - r.mean * r.mean);
  return r;
}

}  // namespace

TEST(tabulated_distribution, NormalisedAndSameInterpolantAsTheTable) {
  const auto& p = beckmann03();
  const auto& t = *p.table;
  EXPECT_NEAR(t.normalisation(), 1.0, 1e-4);
  for (int k = 0; k < 20; ++k) {
    Vec3 m = direction(4.0 * k, 17.0 * k);
    EXPECT_DOUBLE_EQ(t.D(m), t.table().eval(m) / t.normalisation());
  }
  // integral D(m)(m.n) dw = 1 (quadrature of the interpolant on a lobe-shaped chart).
  mtest::Chart chart(mtest::lobe_stretch(0.3, 0.3, 0));
  EXPECT_NEAR(chart.integrate([&](const Vec3& m) { return t.D(m) * m.z(); }, 512, 512), 1.0, 2e-4);
  EXPECT_NEAR(t.sigma_plus(Vec3(0, 0, 1)), 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(t.G1(Vec3(0, 0, 1)), 1.0);
}

TEST(tabulated_distribution, G1MatchesAnalyticSmith) {
  // docs/theory.md §9 item 5: G1 of a tabulated Beckmann/GGX = the analytic Smith G1.
  // sigma+ integrates the table's interpolant (see WeakWhiteFurnace), so what is left is how
  // well the 513^2 table represents the model: Beckmann vanishes at the horizon and agrees to
  // ~2e-5; GGX keeps D ~ alpha^2/pi at the horizon, which the node-centred table (nodes on the
  // rim are 0, bilinear cells cut by the circle) under-represents where the 1/m_z of sigma+
  // weights it most: up to 3.6e-3 at alpha 0.3 (2.6e-3 at 1025^2; it scales like sqrt(Delta)).
  double worst_direct = 0;
  const Pair beckmann_default_bins =
      make_pair(NdfSpec{"beckmann", 0.3, 0.3, 0, 0, 0, 0, {}}, 513, 256);
  for (const Pair* p : {&beckmann03(), &ggx03(), &beckmann_aniso(), &beckmann_default_bins}) {
    const bool ggx = p == &ggx03();
    const double tol = ggx ? 4e-3 : p == &beckmann_default_bins ? 5e-5 : 2e-4;
    double w = 0;
    for (double th = 0; th <= 88.01; th += 2)
      for (double ph : {0.0, 33.0, 90.0, 157.0, 245.0}) {
        Vec3 v = direction(th, ph);
        const double ga = p->analytic->G1(v), gt = p->table->G1(v);
        EXPECT_NEAR(gt, ga, tol) << p->analytic->describe() << " theta " << th << " phi " << ph;
        w = std::max(w, std::abs(gt - ga));
        const double gd = std::min(1.0, v.z() / p->table->sigma_plus_direct(v));
        worst_direct = std::max(worst_direct, std::abs(gd - gt));
      }
    std::printf("%s, %zu^2 bins: max |G1 tabulated - G1 Smith| over theta 0..88 deg: %.2e\n",
                p->analytic->describe().c_str(), p->table->sigma_bins(), w);
  }
  // The (theta, phi) grid interpolation against the direct bin sums.
  EXPECT_LT(worst_direct, 1e-4);
  std::printf("max |G1 grid-interpolated - G1 direct bin sums|: %.2e\n", worst_direct);
}

// The sigma+ grid holds the direct slope-bin sums (four running sums, two bins per SSE2
// instruction) at its nodes (1 deg x 2 deg): on a node direction the interpolation returns the
// node's value, so the grid and sigma_plus_direct agree to rounding there (and G1MatchesAnalytic
// Smith checks the direct sums against Smith's G1).
TEST(tabulated_distribution, SigmaGridEqualsDirectBinSumsAtNodes) {
  const auto& t = *beckmann_aniso().table;
  for (int it : {0, 1, 17, 45, 80, 89})
    for (int ip : {0, 1, 44, 91, 179}) {
      const Vec3 k = direction(it, 2 * ip);
      EXPECT_NEAR(t.sigma_plus(k), t.sigma_plus_direct(k), 1e-12) << it << " " << ip;
    }
}

TEST(tabulated_distribution, WeakWhiteFurnace) {
  // integral G1(v) D(m) <v.m>+ dw / (v.n) = sigma+_true(v) / sigma+_grid(v) = 1, with sigma+_true
  // integrated from the interpolant on a chart (independent of the slope bins and the grid).
  double worst = 0;
  for (const Pair* p : {&beckmann03(), &ggx03(), &beckmann_aniso()}) {
    const auto& t = *p->table;
    mtest::Chart chart(mtest::lobe_stretch(0.35, 0.35, 0));
    for (double th : {0.0, 30.0, 60.0, 75.0, 85.0})
      for (double ph : {0.0, 110.0}) {
        Vec3 v = direction(th, ph);
        const double i = chart.integrate(
            [&](const Vec3& m) { return t.G1(v) * t.D(m) * std::max(0.0, v.dot(m)); }, 384, 384);
        EXPECT_NEAR(i / v.z(), 1.0, 1e-3) << t.describe() << " theta " << th;
        worst = std::max(worst, std::abs(i / v.z() - 1));
      }
  }
  std::printf("weak white furnace, tabulated Beckmann/GGX, theta_v <= 85 deg: max |I - 1| %.2e\n",
              worst);
}

TEST(tabulated_distribution, BrdfReciprocityAndAgreementWithAnalytic) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  auto cu = std::make_shared<ConductorFresnel>(metal("Cu"));
  double worst_rel = 0;
  for (const Pair* p : {&beckmann03(), &ggx03(), &beckmann_aniso()}) {
    MicrofacetBrdf bt(p->table, cu), ba(p->analytic, cu);
    for (int k = 0; k < 300; ++k) {
      Vec3 wi = direction(89 * u(rng), 360 * u(rng)), wo = direction(89 * u(rng), 360 * u(rng));
      const double f1 = bt.eval(wi, wo, 550e-9), f2 = bt.eval(wo, wi, 550e-9);
      EXPECT_NEAR(f1, f2, 1e-12 * std::max(1.0, f1));
    }
    // Slices away from grazing: within a few percent where the lobe is significant.
    for (double ti : {0.0, 30.0, 60.0})
      for (auto plane : {SlicePlane::In, SlicePlane::Out}) {
        auto st = tabulate_slice(bt, ti * mtest::kPi / 180, 550e-9, plane, 181);
        auto sa = tabulate_slice(ba, ti * mtest::kPi / 180, 550e-9, plane, 181);
        const double peak = *std::max_element(sa.value.begin(), sa.value.end());
        for (std::size_t i = 0; i < st.value.size(); ++i) {
          if (std::abs(st.angle_deg[i]) > 70 || sa.value[i] < 0.01 * peak) continue;
          const double rel = std::abs(st.value[i] / sa.value[i] - 1);
          EXPECT_LT(rel, 0.03) << p->analytic->describe() << " theta_i " << ti << " angle "
                               << st.angle_deg[i];
          worst_rel = std::max(worst_rel, rel);
        }
      }
  }
  std::printf("tabulated vs analytic BRDF slices (|angle| <= 70, f >= 1%% of peak): max rel %.2e\n",
              worst_rel);
}

TEST(tabulated_distribution, SamplingPdfAndWeightsExact) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(0, 1);
  auto al = std::make_shared<ConductorFresnel>(metal("Al"));
  for (const Pair* p : {&beckmann03(), &ggx03(), &beckmann_aniso(), &beckmann03_ndf()}) {
    const auto& t = *p->table;
    MicrofacetBrdf b(p->table, al);
    if (t.sampling() == TabulatedSampling::Ndf) {  // the plain sampler: D(m)(m.n) whatever wi
      Vec3 m = t.sample_visible(direction(70, 10), 0.3, 0.6);
      EXPECT_NEAR(t.sampling_pdf(direction(70, 10), m), t.D(m) * m.z(), 1e-15);
      EXPECT_NEAR(t.sampling_pdf(direction(10, 200), m), t.D(m) * m.z(), 1e-15);
    }
    for (int k = 0; k < 300; ++k) {
      Vec3 wi = direction(85 * u(rng), 360 * u(rng));
      Vec3 m = t.sample_visible(wi, u(rng), u(rng));
      EXPECT_GT(m.z(), 0);
      EXPECT_GT(t.sampling_pdf(wi, m), 0);
      auto smp = b.sample(wi, u(rng), u(rng), 600e-9);
      if (!smp) continue;
      const double f = b.eval(wi, smp->wo, 600e-9), q = b.pdf(wi, smp->wo);
      EXPECT_NEAR(smp->pdf, q, 1e-9 * q);
      EXPECT_NEAR(smp->weight, f * smp->wo.z() / q, 1e-9 * std::max(1.0, smp->weight));
    }
  }
}

TEST(tabulated_distribution, SampledDirectionsFollowPdfChiSquare) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> u(0, 1);
  auto mirror = std::make_shared<PerfectMirrorFresnel>();
  int c = 0;
  for (const Pair* p : {&beckmann03(), &ggx03(), &beckmann_aniso()}) {
    MicrofacetBrdf b(p->table, mirror);
    for (double th : {20.0, 60.0}) {
      Vec3 wi = direction(th, 30);
      const int total = 200000;
      std::vector<Vec3> s;
      s.reserve(total);
      int absorbed = 0;
      while (static_cast<int>(s.size()) + absorbed < total) {
        auto smp = b.sample(wi, u(rng), u(rng), 550e-9);
        if (smp)
          s.push_back(smp->wo);
        else
          ++absorbed;
      }
      const double kept = static_cast<double>(s.size()) / total;
      mtest::Chart plain(Eigen::Matrix3d::Identity());
      auto r = mtest::chi_square(
          plain, s, [&](const Vec3& wo) { return b.pdf(wi, wo) / kept; }, 0.01 / 6);
      EXPECT_LT(r.chi2, r.critical) << b.describe() << " theta_i " << th;
      EXPECT_NEAR(r.total_expected, 1.0, 5e-3) << b.describe();
      std::printf("%s, theta_i %.0f: chi2/dof %.3f (dof %d, critical %.1f), kept %.4f\n",
                  p->analytic->describe().c_str(), th, r.chi2 / r.dof, r.dof, r.critical, kept);
      ++c;
    }
  }
  EXPECT_EQ(c, 6);
}

TEST(tabulated_distribution, AlbedoAgreesWithAnalyticAndStaysBelowOne) {
  auto mirror = std::make_shared<PerfectMirrorFresnel>();
  for (const Pair* p : {&beckmann03(), &ggx03()}) {
    MicrofacetBrdf bt(p->table, mirror), ba(p->analytic, mirror);
    for (double th : {0.0, 45.0, 70.0}) {
      Vec3 wi = direction(th, 0);
      const double at = directional_albedo(bt, wi, 550e-9, 96, 192),
                   aa = directional_albedo(ba, wi, 550e-9, 96, 192),
                   as = directional_albedo_sampled(bt, wi, 550e-9, 256);
      EXPECT_LE(at, 1.0 + 1e-3);
      EXPECT_NEAR(at, aa, 5e-3) << p->analytic->describe() << " theta_i " << th;
      EXPECT_NEAR(as, at, 1e-2) << p->analytic->describe() << " theta_i " << th;
    }
  }
}

TEST(tabulated_distribution, RejectsEmptyTable) {
  TabulatedNdf empty(65);
  EXPECT_THROW(TabulatedDistribution{std::move(empty)}, InputError);
}

// Chi-square of the microfacet normals drawn by sample_visible against sampling_pdf, binned in
// disk coordinates (m_x, m_y) on blocks of 2 x 2 table cells: inside a table cell the density
// per unit disk area, sampling_pdf / m_z, is bilinear (the visible sampler's coarse cells are
// unions of table cells), so 2 x 2 Gauss points per cell give the expected counts exactly
// (away from the rim, where these lobes have no mass). sampling_pdf is evaluated pointwise
// through the public interface only.
TEST(tabulated_distribution, VisibleSamplingFollowsPdfChiSquare) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> u(0, 1);
  int tests = 0;
  for (const Pair* p : {&narrow(), &beckmann03()}) {
    const auto& t = *p->table;
    ASSERT_EQ(t.sampling(), TabulatedSampling::Visible);
    const std::size_t cells = t.table().resolution() - 1, nb = cells / 2;
    const double h = t.table().spacing();
    for (double th : {0.0, 45.0, 75.0, 85.0}) {
      const Vec3 wi = direction(th, 70);
      std::vector<double> expected(nb * nb, 0), observed(nb * nb, 0);
      const double g = 0.5 / std::sqrt(3.0);
      double total = 0;
      for (std::size_t cy = 0; cy < cells; ++cy)
        for (std::size_t cx = 0; cx < cells; ++cx) {
          double e = 0;
          for (double ty : {0.5 - g, 0.5 + g})
            for (double tx : {0.5 - g, 0.5 + g}) {
              const double x = t.table().node_x(cx) + tx * h, y = t.table().node_y(cy) + ty * h,
                           r2 = x * x + y * y;
              if (r2 >= 1) continue;
              const double z = std::sqrt(1 - r2);
              e += t.sampling_pdf(wi, Vec3(x, y, z)) / z;
            }
          e *= 0.25 * h * h;
          expected[(cy / 2) * nb + cx / 2] += e;
          total += e;
        }
      EXPECT_NEAR(total, 1.0, 1e-6) << t.describe() << " theta " << th;
      const int n = 400000;
      for (int k = 0; k < n; ++k) {
        const Vec3 m = t.sample_visible(wi, u(rng), u(rng));
        ASSERT_GT(m.z(), 0);
        ASSERT_NEAR(m.norm(), 1.0, 1e-12);
        const auto bx = std::min(static_cast<std::size_t>((m.x() + 1) / h), cells - 1) / 2,
                   by = std::min(static_cast<std::size_t>((m.y() + 1) / h), cells - 1) / 2;
        observed[by * nb + bx] += 1;
      }
      std::vector<double> counts(expected.size());
      for (std::size_t b = 0; b < expected.size(); ++b) counts[b] = expected[b] * n;
      const auto c = mtest::pooled_chi_square(observed, counts, 0.01 / 8);
      EXPECT_LT(c.chi2, c.critical) << t.describe() << " theta " << th;
      std::printf("%s, theta_v %.0f: chi2/dof %.3f (dof %d, critical %.1f)\n",
                  p->analytic->describe().c_str(), th, c.chi2 / c.dof, c.dof, c.critical);
      ++tests;
    }
  }
  EXPECT_EQ(tests, 8);
}

// A table whose mass covers only part of the disk (zero for m_x < -0.3 and m_y > 0.45, so
// rows of coarse cells with no mass and rows whose cells with mass start mid-row): the view
// tables keep only each row's span of cells with mass, in float. The pdf still integrates to 1
// over the disk and a histogram of samples follows it (chi-square over 4 x 4 cell blocks),
// at normal, oblique and grazing views, also between view nodes.
TEST(tabulated_distribution, VisibleSamplingPartialSupportFollowsPdf) {
  auto a = make_distribution(NdfSpec{"beckmann", 0.35, 0.25, 0.3, 0, 0, 0, {}});
  TabulatedNdf tab = tabulate(*a, "beckmann", 129);
  for (std::size_t iy = 0; iy < tab.resolution(); ++iy)
    for (std::size_t ix = 0; ix < tab.resolution(); ++ix)
      if (tab.node_x(ix) < -0.3 || tab.node_y(iy) > 0.45) tab.at(ix, iy) = 0;
  TabulatedDistributionOptions o;
  o.vn_coarse = 32;  // 4 x 4 cells each
  const TabulatedDistribution t(tab, o);
  const std::size_t cells = tab.resolution() - 1, nb = cells / 4;
  const double h = tab.spacing(), g = 0.5 / std::sqrt(3.0);
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> u(0, 1);
  for (const auto& [th, ph] : {std::pair{0.0, 0.0}, {37.0, 101.0}, {62.5, 250.0}, {86.0, 3.0}}) {
    const Vec3 wi = direction(th, ph);
    std::vector<double> expected(nb * nb, 0), observed(nb * nb, 0);
    double total = 0;
    for (std::size_t cy = 0; cy < cells; ++cy)
      for (std::size_t cx = 0; cx < cells; ++cx) {
        double e = 0;
        for (double ty : {0.5 - g, 0.5 + g})
          for (double tx : {0.5 - g, 0.5 + g}) {
            const double x = tab.node_x(cx) + tx * h, y = tab.node_y(cy) + ty * h,
                         r2 = x * x + y * y;
            if (r2 >= 1) continue;
            const double z = std::sqrt(1 - r2);
            e += t.sampling_pdf(wi, Vec3(x, y, z)) / z;
          }
        e *= 0.25 * h * h;
        if (tab.node_x(cx + 1) <= -0.3 || tab.node_y(cy) >= 0.45) {
          EXPECT_EQ(e, 0.0);
        }
        expected[(cy / 4) * nb + cx / 4] += e;
        total += e;
      }
    // (2 x 2 Gauss per cell: exact for the bilinear density times m_z / m_z inside the disk;
    // the rim cells' quadrature error is small at this lobe width)
    EXPECT_NEAR(total, 1.0, 2e-4) << "theta " << th;
    const int n = 300000;
    for (int k = 0; k < n; ++k) {
      const Vec3 m = t.sample_visible(wi, u(rng), u(rng));
      ASSERT_GT(m.z(), 0);
      ASSERT_GE(m.x(), -0.3 - h);
      ASSERT_LE(m.y(), 0.45 + h);
      const auto bx = std::min(static_cast<std::size_t>((m.x() + 1) / h), cells - 1) / 4,
                 by = std::min(static_cast<std::size_t>((m.y() + 1) / h), cells - 1) / 4;
      observed[by * nb + bx] += 1;
    }
    std::vector<double> counts(expected.size());
    for (std::size_t b = 0; b < expected.size(); ++b) counts[b] = expected[b] * n;
    const auto c = mtest::pooled_chi_square(observed, counts, 0.01 / 4);
    EXPECT_LT(c.chi2, c.critical) << "theta " << th;
    std::printf("partial support, theta_v %.1f: chi2/dof %.3f (dof %d)\n", th, c.chi2 / c.dof,
                c.dof);
  }
  // The view tables: (18 + 1) x 24 of them, float, only the rows' spans of cells with mass, so
  // well below nc (nc + 1) doubles each.
  EXPECT_LT(t.sampling_memory_bytes(), 19u * 24u * 32u * 33u * sizeof(double) / 2);
}

// The point of the visible sampler: the variance of the per-sample albedo weight (perfect
// mirror Fresnel, height-correlated G2) drops against the plain D(m)(m.n) sampler on the same
// table, most at grazing light; and both estimators are unbiased (they agree within their
// noise, and with the quadrature albedo for the wide lobe).
TEST(tabulated_distribution, VisibleSamplingReducesAlbedoVarianceUnbiased) {
  auto mirror = std::make_shared<PerfectMirrorFresnel>();
  const int n = 200000;
  struct Case {
    const Pair* vis;
    const Pair* ndf;
    bool quadrature;
  };
  for (const Case& c :
       {Case{&narrow(), &narrow_ndf(), false}, Case{&beckmann03(), &beckmann03_ndf(), true}}) {
    MicrofacetBrdf bv(c.vis->table, mirror), bn(c.ndf->table, mirror);
    for (double th : {0.0, 45.0, 75.0, 85.0}) {
      const Vec3 wi = direction(th, 70);
      const WeightStats sv = weight_stats(bv, wi, n, 31), sn = weight_stats(bn, wi, n, 32);
      const double factor = sn.var / sv.var;
      const double sigma = std::sqrt((sv.var + sn.var) / n);
      EXPECT_NEAR(sv.mean, sn.mean, 4 * sigma) << c.vis->analytic->describe() << " theta " << th;
      double quad = std::nan("");
      if (c.quadrature) {
        quad = directional_albedo(bv, wi, 550e-9, 192, 384);
        EXPECT_NEAR(sv.mean, quad, 4 * std::sqrt(sv.var / n) + 2e-3)
            << c.vis->analytic->describe() << " theta " << th;
      }
      // Normal incidence: the visible normals are D(m)(m.n) already, so both samplers draw
      // from the same density up to the float view CDFs (each coarse-cell probability off by at
      // most a few 2^-24, absolute) and the factor is 1 up to the noise of the variance
      // estimates (driven by rare grazing wo): checked on the pdf instead.
      if (th == 0) {
        const double peak = c.ndf->table->sampling_pdf(wi, Vec3(0, 0, 1));
        for (double a : {0.0, 1.0, 2.0, 4.0}) {
          const Vec3 m = direction(a * 3, 40 * a);
          const double pn = c.ndf->table->sampling_pdf(wi, m);
          EXPECT_NEAR(c.vis->table->sampling_pdf(wi, m), pn, 1e-9 * pn + 1e-6 * peak);
        }
      } else {
        EXPECT_GT(factor, th < 60 ? 1.5 : 3.0) << c.vis->analytic->describe() << " theta " << th;
      }
      std::printf(
          "%s, theta_i %.0f: albedo visible %.5f +- %.1e, ndf %.5f +- %.1e, quadrature %.5f; "
          "weight variance ndf %.3e / visible %.3e = %.2f\n",
          c.vis->analytic->describe().c_str(), th, sv.mean, std::sqrt(sv.var / n), sn.mean,
          std::sqrt(sn.var / n), quad, sn.var, sv.var, factor);
    }
  }
}

TEST(tabulated_distribution, SamplingOptionsParseAndValidate) {
  EXPECT_EQ(parse_tabulated_sampling("visible"), TabulatedSampling::Visible);
  EXPECT_EQ(parse_tabulated_sampling("ndf"), TabulatedSampling::Ndf);
  EXPECT_EQ(to_string(TabulatedSampling::Ndf), "ndf");
  EXPECT_THROW(parse_tabulated_sampling("vndf"), InputError);
  auto a = make_distribution(NdfSpec{"beckmann", 0.3, 0.3, 0, 0, 0, 0, {}});
  TabulatedDistributionOptions o;
  o.vn_defensive = 0;
  EXPECT_THROW(TabulatedDistribution(tabulate(*a, "beckmann", 65), o), InputError);
  o.vn_defensive = 0.05;
  TabulatedDistribution small(tabulate(*a, "beckmann", 65), o);  // coarse > cells: clamped
  EXPECT_GT(small.sampling_memory_bytes(), 0u);
  const Vec3 wi = direction(60, 0);
  const Vec3 m = small.sample_visible(wi, 0.25, 0.75);
  EXPECT_GT(small.sampling_pdf(wi, m), 0);
}

// The renderer's split calls (lookup, view_mix, sample_visible / sampling_pdf with the view's mix
// and the look-up) give bit for bit what D, sample_visible and sampling_pdf give, and D what the
// table's own bilinear evaluation gives: on a whole-disk table with large regions of exact zeros
// (a narrow lobe: the skipped cells), on a zoomed window, and with the plain sampler.
TEST(tabulated_distribution, RendererLookupsEqualTheDefinitions) {
  const auto narrow = make_distribution(NdfSpec{"beckmann", 0.06, 0.2, 0.4, 0, 0, 0, {}});
  TabulatedNdf zoomed(129, zoom_window(0.1, -0.05, 0.4));
  for (std::size_t iy = 0; iy < 129; ++iy)
    for (std::size_t ix = 0; ix < 129; ++ix) {
      const double x = zoomed.node_x(ix), y = zoomed.node_y(iy), r2 = x * x + y * y;
      if (r2 < 1) zoomed.at(ix, iy) = narrow->D(Vec3(x, y, std::sqrt(1 - r2)));
    }
  TabulatedNdf sparse = tabulate(*narrow, "beckmann", 257);
  for (double& v : sparse.values())
    if (v < 1e-3) v = 0;  // exact zeros over most of the disk
  TabulatedDistributionOptions small;
  small.sigma_bins = 64;
  TabulatedDistributionOptions plain = small;
  plain.sampling = TabulatedSampling::Ndf;
  const TabulatedDistribution dists[] = {TabulatedDistribution(sparse, small),
                                         TabulatedDistribution(zoomed, small),
                                         TabulatedDistribution(sparse, plain)};
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  for (const auto& d : dists) {
    const double inv_z = 1 / d.normalisation();
    int nonzero = 0, zero = 0, sampled = 0;
    for (int i = 0; i < 20000; ++i) {
      const Vec3 v = direction(89.9 * std::sqrt(u(rng)), 360 * u(rng));
      // Normals over the whole hemisphere, not all of unit length, a few below the horizon.
      const Vec3 m = direction(92 * u(rng), 360 * u(rng)) * (0.5 + u(rng));
      TabulatedLookup q;
      const double dm = d.lookup(m, q);
      ASSERT_EQ(dm, d.table().eval(m) * inv_z) << i;
      ASSERT_EQ(dm, d.D(m));
      (dm != 0 ? nonzero : zero)++;
      const TabulatedViewMix x = d.view_mix(v);
      d.prefetch_pdf(x, q);
      ASSERT_EQ(d.sampling_pdf(x, m, q), d.sampling_pdf(v, m)) << i;
      const double u1 = u(rng), u2 = u(rng);
      const Vec3 s = d.sample_visible(x, v, u1, u2);
      ASSERT_EQ(s, d.sample_visible(v, u1, u2)) << i;
      TabulatedLookup qs;
      d.lookup(s, qs);
      const double ps = d.sampling_pdf(x, s, qs);
      ASSERT_EQ(ps, d.sampling_pdf(v, s));
      sampled += ps > 0;
    }
    EXPECT_GT(nonzero, 1000);
    EXPECT_GT(zero, 1000);
    EXPECT_GT(sampled, 19000);
  }
}

// The visible-normal sampler's searches count entries (SSE2) instead of halving: the same index
// and the same rescaled number as detail::pick's binary search, for float and double CDFs with
// ties, zero-width intervals and numbers on and next to the entries.
template <class T>
void expect_counted_pick_equals_pick(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  for (int trial = 0; trial < 400; ++trial) {
    const std::size_t n = 1 + trial % 131;
    std::vector<double> w(n);
    for (double& x : w) x = u(rng) < 0.3 ? 0.0 : std::floor(8 * u(rng));  // ties and zeros
    w[n - 1] += 1;
    double total = 0;
    for (double x : w) total += x;
    std::vector<T> cdf(n);
    double run = 0;
    for (std::size_t i = 0; i < n; ++i) cdf[i] = static_cast<T>((run += w[i]) / total);
    cdf[n - 1] = 1;
    std::vector<double> us = {0.0, std::nextafter(1.0, 0.0)};
    for (int k = 0; k < 20; ++k) us.push_back(u(rng));
    for (T c : cdf) {
      const double e = static_cast<double>(c);
      for (double x : {e, std::nextafter(e, 0.0), std::nextafter(e, 2.0)})
        if (x >= 0 && x < 1) us.push_back(x);
    }
    for (double x : us) {
      double r0 = -1, r1 = -2;
      const std::size_t i0 = detail::pick(cdf.data(), n, x, r0);
      const std::size_t i1 = detail::pick_counted(cdf.data(), n, x, r1, true);
      ASSERT_EQ(i0, i1) << n << " " << x;
      ASSERT_EQ(r0, r1) << n << " " << x;
    }
  }
}

TEST(tabulated_distribution, CountedSearchEqualsTheBinarySearch) {
  std::mt19937_64 rng(9);
  expect_counted_pick_equals_pick<float>(rng);
  expect_counted_pick_equals_pick<double>(rng);
}

// The renderer's material on a tabulated NDF: the MIS density of a light direction and of the
// BRDF sample is exactly the distribution's sampling_pdf(wv, h) / (4 wv.h) (computed from the
// look-up shared with D(h) and the view's mix), and the sample is sample_visible's.
TEST(tabulated_distribution, RendererMaterialDensitiesEqualTheDistributions) {
  auto d = std::make_shared<TabulatedDistribution>(tabulate(
      *make_distribution(NdfSpec{"beckmann", 0.25, 0.1, 0.3, 0, 0, 0, {}}), "beckmann", 257));
  auto b = std::make_shared<MicrofacetBrdf>(d, std::make_shared<ConductorFresnel>(metal("Cu")));
  const pt::SpectralMaterial mat(std::make_shared<UniformSvbrdf>(b));
  ASSERT_TRUE(mat.fast());
  const double lambda[4] = {400e-9, 500e-9, 600e-9, 700e-9};
  pt::SpectralMaterial::Wavelengths w;
  mat.prepare(lambda, 4, w);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  int lit = 0, sampled = 0;
  for (int i = 0; i < 3000; ++i) {
    const Vec3 wv = direction(88 * std::sqrt(u(rng)), 360 * u(rng));
    const Vec3 wl = direction(89 * u(rng), 360 * u(rng));
    const auto view = mat.view(wv);
    const Vec3 hs = wl + wv, h = hs / hs.norm();
    const double ref = d->sampling_pdf(wv, h) / (4 * wv.dot(h));
    double f[4], pdf = 0;
    if (mat.eval(0, 0, view, wl, w, f, &pdf)) {
      ++lit;
      ASSERT_EQ(pdf, ref) << i;
    }
    ASSERT_EQ(mat.sampling_pdf(0, 0, view, wl), ref) << i;
    const double u1 = u(rng), u2 = u(rng);
    pt::SpectralMaterial::Sample s;
    if (mat.sample(0, 0, view, u1, u2, w, s)) {
      ++sampled;
      const Vec3 m = d->sample_visible(wv, u1, u2);
      const double im = wv.dot(m);
      ASSERT_EQ(s.wo, 2 * im * m - wv);
      ASSERT_EQ(s.pdf, d->sampling_pdf(wv, m) / (4 * im));
      ASSERT_EQ(s.target, d->D(m) / (4 * view.pa));
    }
  }
  EXPECT_GT(lit, 1000);
  EXPECT_GT(sampled, 2000);
}
