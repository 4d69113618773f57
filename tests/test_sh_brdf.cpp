// ShBrdf (W92 section 2, docs/theory.md §6.3, 6.5, 6.6): the exact Lambertian matrix, projection of
// analytic BRDFs, reciprocity, albedo, damping, .shbrdf files, and sampling (pdf consistency,
// histogram chi-square, sampled albedo, many threads).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <thread>
#include <vector>

#include "microbrdf/brdf.hpp"
#include "microbrdf/brdf_albedo.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/quadrature.hpp"
#include "microbrdf/sh_basis.hpp"
#include "microbrdf/sh_brdf.hpp"

using namespace microbrdf;

namespace {
constexpr double kPi = 3.14159265358979323846;

Vec3 dir(double theta_deg, double phi_deg) {
  const double t = theta_deg * kPi / 180, p = phi_deg * kPi / 180;
  return Vec3(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
}

class Lambert final : public Brdf {
 public:
  explicit Lambert(double a) : a_(a) {}
  double eval(const Vec3& wi, const Vec3& wo, double) const override {
    return wi.z() > 0 && wo.z() > 0 ? a_ / kPi : 0.0;
  }
  std::optional<BrdfSample> sample(const Vec3&, double, double, double) const override {
    return std::nullopt;
  }
  double pdf(const Vec3&, const Vec3&) const override { return 0; }
  std::string describe() const override { return "Lambert"; }

 private:
  double a_;
};

Eigen::MatrixXd lambert_matrix(int lmax, double a) {
  ShOddBasis b(lmax);
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(b.size(), b.size());
  m(sh_odd_index(1, 0), sh_odd_index(1, 0)) = 4 * a / 3;
  return m;
}

MicrofacetBrdf ggx(double ax, double ay, double phi) {
  return MicrofacetBrdf(std::make_shared<GgxDistribution>(ax, ay, phi),
                        std::make_shared<PerfectMirrorFresnel>());
}

std::string temp_path(const std::string& stem) {
  return ::testing::TempDir() + "/" + stem + "-" + std::to_string(::getpid());
}
}  // namespace

TEST(sh_brdf, LambertianMatrixIsExact) {
  ShBrdf b(6, lambert_matrix(6, 0.7));
  for (double ti : {0.0, 30.0, 60.0, 85.0})
    for (double to : {0.0, 45.0, 80.0}) {
      EXPECT_NEAR(b.eval(dir(ti, 10), dir(to, 200), 0), 0.7 / kPi, 1e-14);
      EXPECT_NEAR(b.cosine_weighted(dir(ti, 10), dir(to, 200)),
                  0.7 / kPi * std::cos(ti * kPi / 180) * std::cos(to * kPi / 180), 1e-14);
    }
  for (double ti : {0.0, 45.0, 89.0}) EXPECT_NEAR(b.albedo(dir(ti, 33)), 0.7, 1e-13);
  EXPECT_EQ(b.eval(dir(30, 0), dir(100, 0), 0), 0.0);
  EXPECT_TRUE(b.isotropic());
}

TEST(sh_brdf, ProjectionOfLambertIsTheSingleCoefficient) {
  const auto b = ShBrdf::project(Lambert(0.5), 8, 555e-9);
  const Eigen::MatrixXd ref = lambert_matrix(8, 0.5);
  EXPECT_LT((b.matrix() - ref).cwiseAbs().maxCoeff(), 1e-13);
}

TEST(sh_brdf, ProjectionConvergesAndIsReciprocal) {
  // A broad anisotropic rotated GGX lobe (F = 1): the truncated expansion approaches the BRDF
  // as lmax grows, reciprocity is exact, albedo() equals quadrature of the expansion.
  const auto g = ggx(0.6, 0.35, 0.5);
  const Vec3 wi = dir(35, 20);
  double err_prev = 1e9;
  for (int L : {6, 12, 18}) {
    const auto s = ShBrdf::project(g, L, 555e-9);
    EXPECT_FALSE(s.isotropic());
    double err = 0, norm = 0;
    for (double to = 5; to < 70; to += 10)
      for (double po = 0; po < 360; po += 30) {
        const Vec3 wo = dir(to, po);
        const double r = g.eval(wi, wo, 0);
        err += (s.eval(wi, wo, 0) - r) * (s.eval(wi, wo, 0) - r);
        norm += r * r;
      }
    err = std::sqrt(err / norm);
    EXPECT_LT(err, err_prev);
    err_prev = err;
    EXPECT_LT((s.matrix() - s.matrix().transpose()).cwiseAbs().maxCoeff(), 0.0 + 1e-300);
    for (int k = 0; k < 20; ++k) {
      const Vec3 a = dir(3 + 4 * k, 17 * k), c = dir(80 - 3 * k, 290 - 11 * k);
      EXPECT_NEAR(s.eval(a, c, 0), s.eval(c, a, 0), 1e-12 * std::max(1.0, s.eval(a, c, 0)));
    }
    // albedo() integrates f unclamped; compare with quadrature of cosine_weighted / cos_i.
    double q = 0;
    std::vector<double> x, w;
    gauss_legendre(64, x, w);
    for (int i = 0; i < 64; ++i)
      for (int p = 0; p < 128; ++p) {
        const double z = 0.5 * (x[i] + 1), sn = std::sqrt(1 - z * z), ph = (p + 0.5) * kPi / 64;
        q += 0.5 * w[i] * kPi / 64 *
             s.cosine_weighted(wi, Vec3(sn * std::cos(ph), sn * std::sin(ph), z));
      }
    EXPECT_NEAR(s.albedo(wi), q / wi.z(), 1e-10);
    // and it approaches the GGX albedo
    if (L == 18) {
      EXPECT_NEAR(s.albedo(wi), directional_albedo(g, wi, 0), 0.01);
    }
  }
  EXPECT_LT(err_prev, 0.05);
}

TEST(sh_brdf, IsotropyDetection) {
  EXPECT_TRUE(ShBrdf::project(ggx(0.4, 0.4, 0), 8, 0).isotropic());
  EXPECT_FALSE(ShBrdf::project(ggx(0.2, 0.6, 0.3), 8, 0).isotropic());
}

TEST(sh_brdf, GibbsDamping) {
  const auto s = ShBrdf::project(ggx(0.3, 0.3, 0), 12, 0);
  const auto d = s.damped(6, 2.0);
  const auto& b = s.basis();
  for (int j = 0; j < b.size(); ++j)
    for (int k = 0; k < b.size(); ++k) {
      auto w = [&](int l) { return l <= 6 ? 1.0 : std::exp(-(l - 6.0) * (l - 6.0) / 8.0); };
      EXPECT_NEAR(d.matrix()(j, k), w(b.l(j)) * w(b.l(k)) * s.matrix()(j, k), 1e-15);
    }
  EXPECT_EQ(d.meta()["damping"]["l_filter"], 6);
  // The Lambertian term (l = 1) is untouched: damping never changes an l <= l_filter BRDF.
  ShBrdf lam(8, lambert_matrix(8, 1.0));
  EXPECT_NEAR(lam.damped(1, 1.0).albedo(dir(40, 0)), 1.0, 1e-14);
  EXPECT_THROW(s.damped(3, 0.0), InputError);
}

TEST(sh_brdf, FileRoundTripAndCorruptFiles) {
  const auto s = ShBrdf::project(ggx(0.5, 0.3, 0.2), 7, 0, 0, {{"scene", "test"}, {"seed", 4}});
  const std::string p = temp_path("rt.shbrdf");
  s.save(p);
  const auto r = ShBrdf::load(p);
  EXPECT_EQ(r.lmax(), 7);
  EXPECT_EQ((r.matrix() - s.matrix()).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(r.meta()["scene"], "test");
  EXPECT_EQ(r.meta()["seed"], 4);
  const auto bytes = s.to_bytes();
  // Every truncation is rejected with FileError naming the file.
  for (std::size_t n = 0; n < bytes.size(); n += 1 + n / 3) {
    try {
      ShBrdf::load_bytes(std::span(bytes.data(), n), "cut.shbrdf");
      ADD_FAILURE() << "accepted " << n << " of " << bytes.size() << " bytes";
    } catch (const FileError& e) {
      EXPECT_EQ(e.path(), "cut.shbrdf");
    }
  }
  auto bad = bytes;
  bad[0] = 'X';
  EXPECT_THROW(ShBrdf::load_bytes(bad, "x"), FileError);
  bad = bytes;
  bad.push_back(0);
  EXPECT_THROW(ShBrdf::load_bytes(bad, "x"), FileError);
  bad = bytes;
  bad[10] = 0x7f;  // header length absurd
  EXPECT_THROW(ShBrdf::load_bytes(bad, "x"), FileError);
  bad = bytes;
  std::uint64_t nan = 0x7ff8000000000000ull;
  std::memcpy(bad.data() + bad.size() - 8, &nan, 8);
  EXPECT_THROW(ShBrdf::load_bytes(bad, "x"), FileError);
  // A finite but absurd coefficient (-1e308: sums with it overflow to inf - inf = NaN in the
  // albedo) is refused too; 1e100 is the bound.
  bad = bytes;
  const double huge = -1e308, big = 1e99;
  std::memcpy(bad.data() + bad.size() - 8, &huge, 8);
  EXPECT_THROW(ShBrdf::load_bytes(bad, "x"), FileError);
  bad = bytes;
  std::memcpy(bad.data() + bad.size() - 8, &big, 8);
  EXPECT_TRUE(std::isfinite(ShBrdf::load_bytes(bad, "x").albedo(Vec3(0.3, 0.1, 0.9).normalized())));
  EXPECT_THROW(ShBrdf::load(p + ".missing"), FileError);
  std::remove(p.c_str());
}

namespace {
// Chi-square of a histogram of sample() over (theta_o, phi_o) bins against the integral of
// pdf() over each bin; returns (chi2, degrees of freedom).
std::pair<double, int> chi_square(const ShBrdf& b, const Vec3& wi, int n) {
  const int nt = 10, np = 20;
  std::vector<double> hist(nt * np, 0.0), expect(nt * np, 0.0);
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < n; ++i) {
    auto s = b.sample(wi, u(rng), u(rng), 0);
    if (!s) continue;
    const double th = std::acos(s->wo.z()), ph = std::atan2(s->wo.y(), s->wo.x()) + kPi;
    const int r = std::min(nt - 1, static_cast<int>(th / (kPi / 2) * nt));
    const int c = std::min(np - 1, static_cast<int>(ph / (2 * kPi) * np));
    hist[r * np + c] += 1;
  }
  std::vector<double> x, w;
  gauss_legendre(8, x, w);
  for (int r = 0; r < nt; ++r)
    for (int c = 0; c < np; ++c)
      for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j) {
          const double th = (r + 0.5 * (x[i] + 1)) * kPi / 2 / nt;
          const double ph = (c + 0.5 * (x[j] + 1)) * 2 * kPi / np - kPi;
          const Vec3 wo(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
          expect[r * np + c] += n * 0.25 * w[i] * w[j] * (kPi / 2 / nt) * (2 * kPi / np) *
                                std::sin(th) * b.pdf(wi, wo);
        }
  double chi2 = 0;
  int dof = 0;
  for (int k = 0; k < nt * np; ++k)
    if (expect[k] > 5) {
      chi2 += (hist[k] - expect[k]) * (hist[k] - expect[k]) / expect[k];
      ++dof;
    }
  return {chi2, dof - 1};
}
}  // namespace

TEST(sh_brdf, SamplingMatchesPdfAndAlbedo) {
  for (bool aniso : {false, true}) {
    const auto g = aniso ? ggx(0.25, 0.5, 0.7) : ggx(0.3, 0.3, 0);
    const auto s = ShBrdf::project(g, 14, 0).damped(10, 3);
    EXPECT_EQ(s.isotropic(), !aniso);
    for (double ti : {0.0, 30.0, 65.0}) {
      const Vec3 wi = dir(ti, 130);
      // pdf integrates to 1 over the hemisphere
      std::vector<double> x, w;
      gauss_legendre(96, x, w);
      double total = 0;
      for (int i = 0; i < 96; ++i)
        for (int p = 0; p < 384; ++p) {
          const double z = 0.5 * (x[i] + 1), sn = std::sqrt(1 - z * z);
          const double ph = (p + 0.5) * 2 * kPi / 384;
          total +=
              0.5 * w[i] * 2 * kPi / 384 * s.pdf(wi, Vec3(sn * std::cos(ph), sn * std::sin(ph), z));
        }
      EXPECT_NEAR(total, 1.0, 2e-3) << ti;
      // sample() returns pdf() and weight = rho cos / pdf
      std::mt19937_64 rng(9);
      std::uniform_real_distribution<double> u(0, 1);
      for (int k = 0; k < 200; ++k) {
        auto smp = s.sample(wi, u(rng), u(rng), 0);
        if (!smp) continue;
        EXPECT_NEAR(smp->pdf, s.pdf(wi, smp->wo), 1e-12 * smp->pdf);
        EXPECT_NEAR(smp->weight, s.eval(wi, smp->wo, 0) * smp->wo.z() / smp->pdf,
                    1e-12 * smp->weight);
      }
      const auto [chi2, dof] = chi_square(s, wi, 100000);
      // 99.9% quantile of chi2(dof) ~ dof + 3.1 sqrt(2 dof) + ... : use a loose bound.
      EXPECT_LT(chi2, dof + 5 * std::sqrt(2.0 * dof)) << "theta_i " << ti << " dof " << dof;
      // The sampled albedo (which clamps rho at 0) agrees with albedo() (unclamped) within the
      // small negative ringing of the damped expansion.
      EXPECT_NEAR(directional_albedo_sampled(s, wi, 0, 200), s.albedo(wi), 0.01) << ti;
    }
  }
}

TEST(sh_brdf, ConcurrentSamplingIsDeterministic) {
  const auto s = ShBrdf::project(ggx(0.2, 0.4, 0.3), 10, 0);
  const Vec3 wi = dir(40, 60);
  auto run = [&](int seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    double acc = 0;
    for (int k = 0; k < 2000; ++k)
      if (auto smp = s.sample(wi, u(rng), u(rng), 0)) acc += smp->weight + smp->wo.x();
    return acc;
  };
  // First use happens concurrently: the table is built once under call_once.
  std::vector<double> par(8);
  std::vector<std::thread> th;
  for (int t = 0; t < 8; ++t) th.emplace_back([&, t] { par[t] = run(t); });
  for (auto& t : th) t.join();
  for (int t = 0; t < 8; ++t) EXPECT_EQ(par[t], run(t));
}

TEST(sh_brdf, IsotropicAverageIsTheRotationMeanAndEvaluatesByBlocks) {
  const auto s = ShBrdf::project(ggx(0.2, 0.5, 0.6), 10, 0);
  EXPECT_FALSE(s.block_diagonal_in_m());
  const auto avg = s.isotropic_average();
  EXPECT_TRUE(avg.block_diagonal_in_m());
  EXPECT_TRUE(avg.isotropic());
  EXPECT_EQ(avg.meta()["isotropic_average"], true);
  auto rot = [](const Vec3& w, double a) {
    return Vec3(std::cos(a) * w.x() - std::sin(a) * w.y(),
                std::sin(a) * w.x() + std::cos(a) * w.y(), w.z());
  };
  for (int k = 0; k < 10; ++k) {
    const Vec3 wi = dir(5 + 8 * k, 31 * k), wo = dir(75 - 7 * k, 200 - 19 * k);
    double mean = 0;
    const int na = 200;
    for (int i = 0; i < na; ++i) {
      const double a = 2 * kPi * i / na;
      mean += s.cosine_weighted(rot(wi, a), rot(wo, a)) / na;
    }
    EXPECT_NEAR(avg.cosine_weighted(wi, wo), mean, 1e-12);
    // the block evaluation equals the dense product
    const int n = avg.basis().size();
    Eigen::VectorXd yi(n), yo(n);
    avg.basis().eval(wi, yi.data());
    avg.basis().eval(wo, yo.data());
    EXPECT_NEAR(avg.cosine_weighted(wi, wo), yi.dot(avg.matrix() * yo), 1e-13);
    // ...and is invariant under rotations about n
    EXPECT_NEAR(avg.cosine_weighted(rot(wi, 0.7), rot(wo, 0.7)), avg.cosine_weighted(wi, wo),
                1e-12);
  }
  // An isotropic lobe is its own average (up to the phi quadrature of the projection).
  const auto iso = ShBrdf::project(ggx(0.3, 0.3, 0), 10, 0);
  EXPECT_LT((iso.isotropic_average().matrix() - iso.matrix()).norm(), 1e-6 * iso.matrix().norm());
  EXPECT_TRUE(ShBrdf(4, lambert_matrix(4, 1)).block_diagonal_in_m());
}

TEST(sh_brdf, BoundEvaluationEqualsEval) {
  const auto s = ShBrdf::project(ggx(0.25, 0.5, 0.3), 12, 0);
  for (int k = 0; k < 10; ++k) {
    const Vec3 a = dir(4 + 8 * k, 37 * k);
    const auto b = s.bind(a);
    for (int q = 0; q < 10; ++q) {
      const Vec3 c = dir(85 - 9 * q, 300 - 23 * q);
      const double f = s.eval(a, c, 0);
      EXPECT_NEAR(s.eval_bound(b, c), f, 1e-12 * std::max(1.0, f));
      EXPECT_NEAR(s.eval_bound(b, c), s.eval(c, a, 0), 1e-12 * std::max(1.0, f));
    }
    EXPECT_EQ(s.eval_bound(b, dir(95, 0)), 0.0);
  }
}
