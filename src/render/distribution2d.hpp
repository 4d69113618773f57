#pragma once
// A piecewise-constant 2D distribution over [0,1)^2 on an nu x nv grid of cells (environment-map
// importance sampling), drawn in O(1) with Walker's alias method (Vose's construction): one
// table access picks the cell, two more uniforms place the point inside it. (The classic
// marginal/conditional CDF inversion needs two binary searches over megabytes of CDFs per
// sample, each step a cache miss; the alias table needs one or two.)

#include <algorithm>
#include <cstdint>
#include <vector>

namespace microbrdf::pt {

class PiecewiseConstant2D {
 public:
  PiecewiseConstant2D() = default;
  /// f[row * nu + col] >= 0 (negative and non-finite values count as 0). All zero: uniform.
  PiecewiseConstant2D(const std::vector<double>& f, std::size_t nu, std::size_t nv)
      : nu_(nu), nv_(nv), cells_(nu * nv) {
    const std::size_t n = nu * nv;
    double sum = 0;
    std::vector<double> w(n);
    for (std::size_t i = 0; i < n; ++i) {
      w[i] = f[i] > 0 && f[i] < 1e300 ? f[i] : 0.0;
      sum += w[i];
    }
    if (!(sum > 0)) {
      w.assign(n, 1.0);
      sum = double(n);
    }
    // Density per unit area of [0,1)^2 is w_i n / sum; scaled weights q_i = w_i n / sum have
    // mean 1.
    std::vector<double> q(n);
    std::vector<std::uint32_t> small, large;
    for (std::size_t i = 0; i < n; ++i) {
      q[i] = w[i] * double(n) / sum;
      cells_[i].density = float(q[i]);
      (q[i] < 1 ? small : large).push_back(std::uint32_t(i));
    }
    while (!small.empty() && !large.empty()) {
      const std::uint32_t s = small.back(), l = large.back();
      small.pop_back();
      cells_[s].prob = float(q[s]);
      cells_[s].alias = l;
      q[l] -= 1 - q[s];
      if (q[l] < 1) {
        large.pop_back();
        small.push_back(l);
      }
    }
    for (auto i : large) cells_[i].prob = 1, cells_[i].alias = i;
    for (auto i : small) cells_[i].prob = 1, cells_[i].alias = i;  // rounding leftovers
  }

  /// (u, v) in [0,1)^2 from three uniforms, with its density per unit area; returns the cell
  /// index (row * nu + col).
  std::size_t sample(double u1, double u2, double u3, double& u, double& v, double& pdf) const {
    const std::size_t n = cells_.size();
    const double x = u1 * double(n);
    std::size_t j = std::min(std::size_t(x), n - 1);
    const double frac = x - double(j);
    if (frac >= cells_[j].prob) j = cells_[j].alias;
    const std::size_t row = j / nu_, col = j % nu_;
    u = (double(col) + u2) / double(nu_);
    v = (double(row) + u3) / double(nv_);
    pdf = cells_[j].density;
    return j;
  }
  /// Density per unit area in cell (col, row).
  double pdf(std::size_t col, std::size_t row) const { return cells_[row * nu_ + col].density; }
  bool empty() const { return cells_.empty(); }

 private:
  struct Cell {
    float prob = 1;           // keep this cell with probability prob, else take alias
    std::uint32_t alias = 0;  // the cell that fills the rest of this slot
    float density = 0;        // density per unit area of [0,1)^2 (w_i n / sum)
  };
  std::size_t nu_ = 0, nv_ = 0;
  std::vector<Cell> cells_;
};

}  // namespace microbrdf::pt
