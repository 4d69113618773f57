#pragma once
// Piecewise-constant 1D and 2D distributions (sampling by inverting the CDF), as used for
// environment-map importance sampling (PBRT 3rd ed. 13.6.7).

#include <algorithm>
#include <cstddef>
#include <vector>

namespace microbrdf::pt {

/// Density over [0, 1) proportional to f[i] on cell i (cells of width 1/n).
class Distribution1D {
 public:
  Distribution1D() = default;
  explicit Distribution1D(const std::vector<double>& f) : f_(f), cdf_(f.size() + 1, 0.0) {
    const std::size_t n = f.size();
    for (std::size_t i = 0; i < n; ++i) cdf_[i + 1] = cdf_[i] + std::max(f[i], 0.0) / double(n);
    integral_ = cdf_[n];
    if (integral_ > 0) {
      for (auto& c : cdf_) c /= integral_;
    } else {
      for (std::size_t i = 0; i <= n; ++i) cdf_[i] = double(i) / double(n);
    }
    cdf_[n] = 1;
  }
  /// Returns x in [0, 1) and its density; `cell` is the index drawn.
  double sample(double u, double& pdf, std::size_t& cell) const {
    const std::size_t n = f_.size();
    auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
    std::size_t i = static_cast<std::size_t>(
        std::clamp<std::ptrdiff_t>((it - cdf_.begin()) - 1, 0, static_cast<std::ptrdiff_t>(n) - 1));
    double du = u - cdf_[i];
    const double w = cdf_[i + 1] - cdf_[i];
    if (w > 0) du /= w;
    pdf = density(i);
    cell = i;
    return std::min((double(i) + du) / double(n), 1.0 - 1e-12);
  }
  /// Density of cell i (per unit of x).
  double density(std::size_t i) const {
    return integral_ > 0 ? std::max(f_[i], 0.0) / integral_ : 1.0;
  }
  double integral() const { return integral_; }
  std::size_t size() const { return f_.size(); }

 private:
  std::vector<double> f_, cdf_;
  double integral_ = 0;
};

/// Density over [0,1)^2 proportional to f[row * nu + col]: a marginal over rows (v) and a
/// conditional per row (u).
class Distribution2D {
 public:
  Distribution2D() = default;
  Distribution2D(const std::vector<double>& f, std::size_t nu, std::size_t nv) {
    rows_.reserve(nv);
    std::vector<double> marg(nv);
    for (std::size_t r = 0; r < nv; ++r) {
      rows_.emplace_back(std::vector<double>(f.begin() + r * nu, f.begin() + (r + 1) * nu));
      marg[r] = rows_.back().integral();
    }
    marginal_ = Distribution1D(marg);
  }
  /// (u, v) in [0,1)^2 with density pdf (per unit area of [0,1)^2).
  void sample(double u1, double u2, double& u, double& v, double& pdf) const {
    double pv, pu;
    std::size_t row, col;
    v = marginal_.sample(u2, pv, row);
    u = rows_[row].sample(u1, pu, col);
    pdf = pu * pv;
  }
  double pdf(std::size_t col, std::size_t row) const {
    return marginal_.density(row) * rows_[row].density(col);
  }
  bool empty() const { return rows_.empty(); }

 private:
  std::vector<Distribution1D> rows_;
  Distribution1D marginal_;
};

}  // namespace microbrdf::pt
