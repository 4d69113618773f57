#pragma once
// Quadrature and chi-square helpers shared by the microfacet, ellipsoid and BRDF tests.
//
// Sphere chart: m = B t / |B t| for t on the unit sphere, with dw_m = |det B| / |B t|^3 dw_t
// (exact for any invertible B). Choosing B to stretch like the lobe (alphas, rotation) resolves
// even alpha = 0.005 with a fixed product grid. The chart is turned so that the horizon m.z = 0
// is the equator t.z = 0, and only t.z > 0 is used.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "microbrdf/microfacet.hpp"
#include "microbrdf/quadrature.hpp"

namespace mtest {

using microbrdf::Vec3;
constexpr double kPi = 3.14159265358979323846;

struct Chart {
  Eigen::Matrix3d b;  // m = b t / |b t|
  double det;
  explicit Chart(const Eigen::Matrix3d& stretch) {
    // Rotate t so that b^T z is along +z: then m.z > 0 <=> t.z > 0.
    Vec3 c = (stretch.transpose() * Vec3(0, 0, 1)).normalized();
    Eigen::Matrix3d q = Eigen::Quaterniond::FromTwoVectors(c, Vec3(0, 0, 1)).toRotationMatrix();
    b = stretch * q.transpose();
    det = std::abs(b.determinant());
  }
  Vec3 m(const Vec3& t) const { return (b * t).normalized(); }
  double jacobian(const Vec3& t) const {
    double l = (b * t).norm();
    return det / (l * l * l);
  }
  Vec3 t_of(const Vec3& m) const { return b.lu().solve(m).normalized(); }
  // Integral over m.z > 0 of f(m) dw_m: Gauss-Legendre in t.z, midpoint in phi.
  double integrate(const std::function<double(const Vec3&)>& f, int nu = 256,
                   int nphi = 256) const {
    std::vector<double> x, w;
    microbrdf::gauss_legendre(nu, x, w);
    double sum = 0;
    for (int i = 0; i < nu; ++i) {
      double u = 0.5 * (x[i] + 1), st = std::sqrt(std::max(0.0, 1 - u * u)), ring = 0;
      for (int j = 0; j < nphi; ++j) {
        double p = 2 * kPi * (j + 0.5) / nphi;
        Vec3 t(st * std::cos(p), st * std::sin(p), u);
        ring += f(m(t)) * jacobian(t);
      }
      sum += 0.5 * w[i] * ring * 2 * kPi / nphi;
    }
    return sum;
  }
};

/// Stretch matching a Beckmann/GGX lobe, deliberately off by factors 1.7 and 0.6 so that the
/// integrand in chart space is not trivially constant.
inline Eigen::Matrix3d lobe_stretch(double ax, double ay, double phi) {
  return microbrdf::rotation_z(phi) *
         Eigen::DiagonalMatrix<double, 3>(1.7 * ax, 0.6 * ay, 1.0).toDenseMatrix();
}

/// Upper quantile z of N(0,1): P(Z > z) = alpha.
inline double normal_upper_quantile(double alpha) {
  double z = 0;
  for (int it = 0; it < 100; ++it) {  // Newton on 0.5 erfc(z / sqrt 2) = alpha
    double f = 0.5 * std::erfc(z / std::sqrt(2.0)) - alpha;
    double d = -std::exp(-0.5 * z * z) / std::sqrt(2 * kPi);
    double dz = f / d;
    z -= dz;
    if (std::abs(dz) < 1e-12) break;
  }
  return z;
}

/// Chi-square critical value at significance alpha (Wilson-Hilferty; fine for dof > 30).
inline double chi2_critical(double dof, double alpha) {
  const double z = normal_upper_quantile(alpha);
  const double a = 2.0 / (9.0 * dof);
  return dof * std::pow(1 - a + z * std::sqrt(a), 3);
}

struct ChiSquare {
  double chi2 = 0, critical = 0, total_expected = 0;
  int dof = 0;
};

/// Bins samples (unit vectors with z > 0) on the chart's upper hemisphere, nu x nphi equal-area
/// bins, against N times the integral of `pdf` (per steradian of m) over each bin (6 x 6 Gauss
/// points per bin). Bins expecting fewer than 5 are pooled. `alpha` is the significance of this
/// one test: a family of k tests at overall 1% uses alpha = 0.01 / k (Bonferroni).
/// Pearson's chi-square of observed counts against expected counts: bins expecting fewer than 5
/// are pooled into one (counted if it expects 5 or more; if it expects fewer but holds more than
/// 20 samples the test fails: samples where the density says none should be), one degree of
/// freedom less for the fixed total. critical: the (1 - alpha) quantile.
inline ChiSquare pooled_chi_square(const std::vector<double>& observed,
                                   const std::vector<double>& expected, double alpha) {
  ChiSquare r;
  double pool_o = 0, pool_e = 0;
  for (std::size_t k = 0; k < observed.size(); ++k) {
    if (expected[k] < 5) {
      pool_o += observed[k];
      pool_e += expected[k];
      continue;
    }
    r.chi2 += (observed[k] - expected[k]) * (observed[k] - expected[k]) / expected[k];
    ++r.dof;
  }
  if (pool_e >= 5) {
    r.chi2 += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
    ++r.dof;
  } else if (pool_o > 20) {
    r.chi2 += 1e9;
  }
  r.dof -= 1;
  r.critical = chi2_critical(r.dof, alpha);
  return r;
}

inline ChiSquare chi_square(const Chart& chart, const std::vector<Vec3>& samples,
                            const std::function<double(const Vec3&)>& pdf, double alpha = 0.01,
                            int nu = 24, int nphi = 48) {
  std::vector<double> observed(static_cast<std::size_t>(nu * nphi), 0),
      expected(observed.size(), 0);
  auto bin_of = [&](const Vec3& m) {
    Vec3 t = chart.t_of(m);
    int iu = std::clamp(static_cast<int>(t.z() * nu), 0, nu - 1);
    double p = std::atan2(t.y(), t.x());
    if (p < 0) p += 2 * kPi;
    int ip = std::clamp(static_cast<int>(p / (2 * kPi) * nphi), 0, nphi - 1);
    return static_cast<std::size_t>(iu * nphi + ip);
  };
  for (const auto& s : samples) observed[bin_of(s)] += 1;
  std::vector<double> gx, gw;
  microbrdf::gauss_legendre(6, gx, gw);
  const double n = static_cast<double>(samples.size());
  for (int iu = 0; iu < nu; ++iu)
    for (int ip = 0; ip < nphi; ++ip) {
      double e = 0;
      for (int a = 0; a < 6; ++a)
        for (int b = 0; b < 6; ++b) {
          double u = (iu + 0.5 * (gx[a] + 1)) / nu, p = 2 * kPi * (ip + 0.5 * (gx[b] + 1)) / nphi;
          double st = std::sqrt(std::max(0.0, 1 - u * u));
          Vec3 t(st * std::cos(p), st * std::sin(p), u);
          e += 0.25 * gw[a] * gw[b] * pdf(chart.m(t)) * chart.jacobian(t);
        }
      expected[static_cast<std::size_t>(iu * nphi + ip)] = e * (1.0 / nu) * (2 * kPi / nphi) * n;
    }
  ChiSquare r = pooled_chi_square(observed, expected, alpha);
  r.total_expected = 0;
  for (double e : expected) r.total_expected += e;
  r.total_expected /= n;
  return r;
}

inline Vec3 direction(double theta_deg, double phi_deg) {
  double t = theta_deg * kPi / 180, p = phi_deg * kPi / 180;
  return Vec3(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
}

}  // namespace mtest
