#pragma once
// A piecewise-bilinear density on the unit square, sampled and inverted continuously through a
// marginal (rows, y) and a conditional (columns, x) CDF, with linear interpolation between
// slices tabulated over up to three parameters. This is the warp the RGL `.bsdf` format is
// defined through (Dupuy & Jakob 2018; the "continuous marginal 2-D" warp of Mitsuba 3 and
// pbrt-v4), see docs/measured.md:
//  - nodes at x = i/(nx-1), y = j/(ny-1); data[slice][j][i] (C order, x fastest);
//  - the slice index is the C-order index over the parameter grids (first parameter slowest);
//    a parameter's weight is linear between its two bracketing nodes, clamped at the ends;
//  - normalised (sampling) mode: each slice is divided by its integral, eval() returns the
//    density per unit area of the square; raw mode: eval() is the bilinear interpolant.
#include <array>
#include <cstddef>
#include <span>
#include <utility>
#include <vector>

namespace microbrdf::detail {

class Marginal2D {
 public:
  Marginal2D() = default;
  /// `params[d]` are the node values of parameter d (strictly increasing, >= 1 node each);
  /// data.size() must be prod(params sizes) * nx * ny, nx, ny >= 2. Sampling mode needs every
  /// slice non-negative with a positive integral. Throws std::invalid_argument otherwise.
  Marginal2D(std::span<const float> data, std::size_t nx, std::size_t ny,
             std::vector<std::vector<double>> params, bool sampling);

  using Vec2 = std::array<double, 2>;
  /// Density (sampling mode) or interpolated value (raw mode) at pos in [0,1]^2.
  double eval(Vec2 pos, const double* param) const;
  /// Maps a uniform point to a point distributed by the density; returns it and the density.
  std::pair<Vec2, double> sample(Vec2 u, const double* param) const;
  /// The inverse of sample(): the uniform point that maps to pos, and the density at pos.
  std::pair<Vec2, double> invert(Vec2 pos, const double* param) const;

  std::size_t nx() const { return nx_; }
  std::size_t ny() const { return ny_; }

 private:
  struct Weights {
    std::array<std::size_t, 8> slice{};
    std::array<double, 8> w{};
    int n = 0;
  };
  Weights weights(const double* param) const;
  double data_at(const Weights& w, std::size_t i) const;
  double cond_at(const Weights& w, std::size_t i) const;
  double marg_at(const Weights& w, std::size_t j) const;

  std::size_t nx_ = 0, ny_ = 0;
  std::vector<std::vector<double>> params_;
  std::vector<std::size_t> strides_;
  bool sampling_ = false;
  std::vector<double> data_, cond_, marg_;
};

}  // namespace microbrdf::detail
