// Real spherical harmonics (docs/theory.md §6.1-6.2): agreement with the C++17 special functions,
// orthonormality by exact quadrature up to lmax 30, parity, the kept basis of the odd completion,
// and which coefficients of an oddly completed function vanish.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "microbrdf/error.hpp"
#include "microbrdf/quadrature.hpp"
#include "microbrdf/sh_basis.hpp"

using namespace microbrdf;

namespace {
constexpr double kPi = 3.14159265358979323846;

Vec3 dir(double theta, double phi) {
  return Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
}

// Y_lm from std::sph_legendre (which carries the Condon-Shortley phase (-1)^m; ours does not).
double reference_y(int l, int m, double theta, double phi) {
  const int am = std::abs(m);
  const double p = (am % 2 ? -1.0 : 1.0) * std::sph_legendre(l, am, theta);
  if (m == 0) return p;
  return std::sqrt(2.0) * p * (m > 0 ? std::cos(am * phi) : std::sin(am * phi));
}

// Gauss-Legendre in z on [-1, 1] (n nodes) x midpoint in phi (2n nodes): exact for products of
// two harmonics of degree < n.
struct SphereRule {
  std::vector<Vec3> d;
  std::vector<double> w;
  explicit SphereRule(int n) {
    std::vector<double> x, gw;
    gauss_legendre(n, x, gw);
    for (int i = 0; i < n; ++i)
      for (int p = 0; p < 2 * n; ++p) {
        const double z = x[i], s = std::sqrt(1 - z * z), ph = (p + 0.5) * kPi / n;
        d.emplace_back(s * std::cos(ph), s * std::sin(ph), z);
        w.push_back(gw[i] * kPi / n);
      }
  }
};
}  // namespace

TEST(sh_basis, MatchesStdSphLegendreUpTo40) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  const int L = 40;
  std::vector<double> y(sh_count(L));
  double worst = 0;
  for (int k = 0; k < 60; ++k) {
    const double th = std::acos(2 * u(rng) - 1), ph = 2 * kPi * u(rng);
    sh_eval(L, dir(th, ph), y.data());
    for (int l = 0; l <= L; ++l)
      for (int m = -l; m <= l; ++m)
        worst = std::max(worst, std::abs(y[sh_index(l, m)] - reference_y(l, m, th, ph)));
  }
  EXPECT_LT(worst, 1e-11);
}

TEST(sh_basis, OrthonormalByQuadratureLmax30) {
  const int L = 30, n = sh_count(L);
  SphereRule rule(L + 2);
  Eigen::MatrixXd y(n, rule.d.size());
  for (std::size_t a = 0; a < rule.d.size(); ++a) sh_eval(L, rule.d[a], y.col(a).data());
  Eigen::Map<const Eigen::VectorXd> w(rule.w.data(), rule.w.size());
  const Eigen::MatrixXd g = y * w.asDiagonal() * y.transpose();
  EXPECT_LT((g - Eigen::MatrixXd::Identity(n, n)).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(sh_basis, StableAtPoleAndHorizonForLmax128) {
  std::vector<double> y(sh_count(kShMaxL));
  for (const Vec3& w : {Vec3(0, 0, 1), Vec3(0, 0, -1), Vec3(1, 0, 0), Vec3(0.6, -0.8, 1e-9),
                        Vec3(1e-12, 0, 1), Vec3(0, 0, 0)}) {
    sh_eval(kShMaxL, w, y.data());
    for (double v : y) ASSERT_TRUE(std::isfinite(v));
  }
  // At the pole only m = 0 survives: Y_l0 = sqrt((2l+1)/4pi).
  sh_eval(kShMaxL, Vec3(0, 0, 1), y.data());
  for (int l = 0; l <= kShMaxL; ++l) {
    EXPECT_NEAR(y[sh_index(l, 0)], std::sqrt((2 * l + 1) / (4 * kPi)), 1e-12 * (l + 1));
    if (l > 0) {
      EXPECT_EQ(y[sh_index(l, 1)], 0.0);
    }
  }
  EXPECT_THROW(sh_eval(kShMaxL + 1, Vec3(0, 0, 1), y.data()), InputError);
  EXPECT_THROW(ShOddBasis(0), InputError);
}

TEST(sh_basis, ParityUnderReflectionInTheSurface) {
  // Y_lm(pi - theta, phi) = (-1)^(l+m) Y_lm(theta, phi)  (docs/theory.md §6.2)
  const int L = 12;
  std::vector<double> a(sh_count(L)), b(sh_count(L));
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  for (int k = 0; k < 50; ++k) {
    const double th = kPi / 2 * u(rng), ph = 2 * kPi * u(rng);
    sh_eval(L, dir(th, ph), a.data());
    sh_eval(L, dir(kPi - th, ph), b.data());
    for (int l = 0; l <= L; ++l)
      for (int m = -l; m <= l; ++m)
        EXPECT_NEAR(b[sh_index(l, m)], ((l + m) % 2 ? -1 : 1) * a[sh_index(l, m)], 1e-13);
  }
}

TEST(sh_basis, OddBasisIsTheKeptHalf) {
  for (int L : {1, 5, 30}) {
    ShOddBasis b(L);
    ASSERT_EQ(b.size(), L * (L + 1) / 2);
    std::vector<double> full(sh_count(L)), odd(b.size());
    const Vec3 w = dir(0.7, 2.1);
    sh_eval(L, w, full.data());
    b.eval(w, odd.data());
    for (int j = 0; j < b.size(); ++j) {
      EXPECT_EQ((b.l(j) + b.m(j)) % 2 != 0, true);
      EXPECT_EQ(sh_odd_index(b.l(j), b.m(j)), j);
      if (j > 0) {
        EXPECT_LT(sh_index(b.l(j - 1), b.m(j - 1)), sh_index(b.l(j), b.m(j)));
      }
      EXPECT_DOUBLE_EQ(odd[j], full[sh_index(b.l(j), b.m(j))]);
    }
  }
}

TEST(sh_basis, HemisphereIntegrals) {
  const int L = 21;
  ShOddBasis b(L);
  // Fine product rule on the upper hemisphere.
  std::vector<double> x, gw, y(b.size());
  const int n = 40;
  gauss_legendre(n, x, gw);
  std::vector<double> ref(b.size(), 0.0);
  for (int i = 0; i < n; ++i)
    for (int p = 0; p < 2 * n; ++p) {
      const double z = 0.5 * (x[i] + 1), s = std::sqrt(1 - z * z), ph = (p + 0.5) * kPi / n;
      b.eval(Vec3(s * std::cos(ph), s * std::sin(ph), z), y.data());
      for (int j = 0; j < b.size(); ++j) ref[j] += 0.5 * gw[i] * kPi / n * y[j];
    }
  for (int j = 0; j < b.size(); ++j) EXPECT_NEAR(b.hemisphere_integrals()[j], ref[j], 1e-12);
  // Y_10 = sqrt(3/4pi) z integrates to sqrt(3/4pi) pi.
  EXPECT_NEAR(b.hemisphere_integrals()[sh_odd_index(1, 0)], std::sqrt(3 / (4 * kPi)) * kPi, 1e-14);
}

TEST(sh_basis, OddCompletionKillsEveryCoefficientWithLPlusMEven) {
  // An anisotropic, off-centre f on the upper hemisphere that vanishes at the horizon, completed
  // by f(x, y, -z) = -f(x, y, z), projected on the full basis: l + m even vanish, l + m odd do
  // not all vanish, and they equal twice the upper-hemisphere integral (the x2 of docs/theory.md
  // §6.4).
  auto g = [](const Vec3& w) {
    return w.z() * std::exp(-((w.x() - 0.3) * (w.x() - 0.3) + 3 * w.y() * w.y() + w.x() * w.y()));
  };
  const int L = 10;
  SphereRule rule(48);
  std::vector<double> y(sh_count(L)), c(sh_count(L), 0.0), upper(sh_count(L), 0.0);
  for (std::size_t a = 0; a < rule.d.size(); ++a) {
    const Vec3& w = rule.d[a];
    const double f = w.z() >= 0 ? g(w) : -g(Vec3(w.x(), w.y(), -w.z()));
    sh_eval(L, w, y.data());
    for (int k = 0; k < sh_count(L); ++k) {
      c[k] += rule.w[a] * f * y[k];
      if (w.z() > 0) upper[k] += rule.w[a] * f * y[k];
    }
  }
  int nonzero_odd = 0, nonzero_even_upper = 0;
  for (int l = 0; l <= L; ++l)
    for (int m = -l; m <= l; ++m) {
      const int k = sh_index(l, m);
      if ((l + m) % 2 == 0) {
        EXPECT_NEAR(c[k], 0.0, 1e-14) << l << " " << m;
        nonzero_even_upper += std::abs(upper[k]) > 1e-3;
      } else {
        nonzero_odd += std::abs(c[k]) > 1e-3;
        EXPECT_NEAR(c[k], 2 * upper[k], 1e-13);
      }
    }
  EXPECT_GT(nonzero_odd, 20);
  EXPECT_GT(nonzero_even_upper, 10);  // without the completion they would not vanish
}

// The batched weighted sum (four directions at a time) equals the sum of single evaluations,
// for counts that are not multiples of four, the pole, a zero vector and non-unit vectors.
TEST(sh_basis, WeightedSumOfManyDirectionsMatchesSingleEvaluations) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int L : {1, 2, 15, 30}) {
    const ShOddBasis b(L);
    for (std::size_t n : {0, 1, 3, 4, 7, 17}) {
      std::vector<Vec3> w(n);
      std::vector<double> r(n);
      for (std::size_t k = 0; k < n; ++k) {
        w[k] = Vec3(u(rng), u(rng), std::abs(u(rng)));
        r[k] = 0.5 + 0.5 * u(rng);
      }
      if (n > 2) w[1] = Vec3(0, 0, 2.5), w[2] = Vec3(0, 0, 0);
      std::vector<double> sum(b.size(), -7.0), y(b.size()), ref(b.size(), 0.0);
      for (std::size_t k = 0; k < n; ++k) {
        b.eval(w[k], y.data());
        for (int j = 0; j < b.size(); ++j) ref[j] += r[k] * y[j];
      }
      b.eval_sum(n, w.data(), r.data(), sum.data());
      for (int j = 0; j < b.size(); ++j)
        ASSERT_NEAR(sum[j], ref[j], 1e-12 * (1 + std::abs(ref[j]))) << L << " " << n << " " << j;
    }
  }
}
