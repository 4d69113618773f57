#pragma once
// A piecewise-constant 2D distribution over [0,1)^2 on an nu x nv grid of cells (environment-map
// importance sampling), drawn by inverting the marginal CDF over rows and then the conditional
// CDF of the chosen row (two binary searches). Inversion is monotone in each uniform, so the
// stratification of a low-discrepancy 2D point (path_sampler.hpp) carries over to the sphere;
// an alias table would be O(1) but scatters neighbouring points to unrelated cells.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace microbrdf::pt {

class PiecewiseConstant2D {
 public:
  PiecewiseConstant2D() = default;
  /// f[row * nu + col] >= 0 (negative and non-finite values count as 0). All zero: uniform.
  PiecewiseConstant2D(const std::vector<double>& f, std::size_t nu, std::size_t nv)
      : nu_(nu), nv_(nv), density_(nu * nv), row_cdf_(nv + 1), col_cdf_((nu + 1) * nv) {
    const std::size_t n = nu * nv;
    std::vector<double> w(n);
    double sum = 0;
    for (std::size_t i = 0; i < n; ++i) {
      w[i] = f[i] > 0 && f[i] < 1e300 ? f[i] : 0.0;
      sum += w[i];
    }
    if (!(sum > 0)) {
      w.assign(n, 1.0);
      sum = double(n);
    }
    // Density per unit area of [0,1)^2 is w_i n / sum (mean 1).
    for (std::size_t i = 0; i < n; ++i) density_[i] = float(w[i] * double(n) / sum);
    row_cdf_[0] = 0;
    for (std::size_t r = 0; r < nv; ++r) {
      double* c = &col_cdf_[r * (nu + 1)];
      c[0] = 0;
      for (std::size_t k = 0; k < nu; ++k) c[k + 1] = c[k] + w[r * nu + k];
      row_cdf_[r + 1] = row_cdf_[r] + c[nu];
    }
  }

  /// (u, v) in [0,1)^2 from two uniforms (u1 -> column within the row, u2 -> row), with its
  /// density per unit area; returns the cell index (row * nu + col).
  std::size_t sample(double u1, double u2, double& u, double& v, double& pdf) const {
    double fv;
    const std::size_t row = invert(row_cdf_.data(), nv_, u2, fv);
    double fu;
    const std::size_t col = invert(&col_cdf_[row * (nu_ + 1)], nu_, u1, fu);
    u = (double(col) + fu) / double(nu_);
    v = (double(row) + fv) / double(nv_);
    const std::size_t j = row * nu_ + col;
    pdf = density_[j];
    return j;
  }
  /// Density per unit area in cell (col, row).
  double pdf(std::size_t col, std::size_t row) const { return density_[row * nu_ + col]; }
  bool empty() const { return density_.empty(); }

 private:
  // The bin k of a CDF c[0..m] (c[0] = 0) with c[k] <= x c[m] < c[k+1], skipping empty bins,
  // and the position within it in [0,1).
  static std::size_t invert(const double* c, std::size_t m, double x, double& frac) {
    const double t = x * c[m];
    std::size_t k = std::size_t(std::upper_bound(c, c + m + 1, t) - c);
    k = std::clamp<std::size_t>(k, 1, m) - 1;
    while (k + 1 < m && !(c[k + 1] > c[k])) ++k;  // t == c[k] at an empty bin
    while (k > 0 && !(c[k + 1] > c[k])) --k;      // rounding past the last non-empty bin
    const double width = c[k + 1] - c[k];
    // Kept 1e-7 of a cell away from its edges, so that the direction built from (u, v) falls
    // back into the same pixel after rounding (a bias of 1e-7 of a pixel).
    frac = width > 0 ? std::clamp((t - c[k]) / width, 1e-7, 1 - 1e-7) : 0.5;
    return k;
  }
  std::size_t nu_ = 0, nv_ = 0;
  std::vector<float> density_;   // per cell, per unit area of [0,1)^2
  std::vector<double> row_cdf_;  // nv + 1 running sums of row weights
  std::vector<double> col_cdf_;  // per row, nu + 1 running sums of its cells
};

}  // namespace microbrdf::pt
