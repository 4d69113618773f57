// Importance sampling of a tabulated NDF, exactly consistent with TabulatedNdf::eval (theory
// notes section 2.4, piecewise-bilinear variant).
//
// Target density on the disk: p(m_x, m_y) = eval_disk(m_x, m_y) / Z (bilinear interpolant of
// the nodes, 0 outside the unit disk), i.e. D(m)(m.n)/Z per steradian.
// Proposal: a cell (c_x, c_y) of the node grid with probability proportional to its full
// bilinear mass Delta^2 (a + b + c + d)/4 (cells that do not meet the disk get 0), chosen by
// a discrete CDF over rows and then over the cells of the row; inside the cell the bilinear
// density is sampled exactly (marginal in y linear, conditional in x linear). Points outside
// the disk (only in cells the circle crosses) are rejected and the whole draw is repeated, so
// the accepted points follow the target exactly. Z = mass of the interpolant inside the disk:
// full masses for cells inside, numerical integration for cells the circle crosses.
#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>

#include "microbrdf/ndf_io.hpp"

namespace microbrdf {
namespace {

constexpr int kMaxTries = 64;
constexpr int kRimRows = 256;  // sub-rows per rim cell (exact integration along x in each)

// Inverse CDF of the linear density on [0, 1] with end values p0, p1 >= 0, written so that it
// is stable for p0 ~ p1 and for either end value 0.
double sample_linear(double u, double p0, double p1) {
  if (p0 == p1) return u;
  const double denom = p0 + std::sqrt(p0 * p0 * (1 - u) + p1 * p1 * u);
  if (!(denom > 0)) return 0.0;
  const double t = u * (p0 + p1) / denom;
  return std::min(t, std::nextafter(1.0, 0.0));
}

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

double to_unit(std::uint64_t h) { return static_cast<double>(h >> 11) * 0x1.0p-53; }

// Mass of the bilinear function with corner values a (x0,y0), b (x1,y0), c (x0,y1), d (x1,y1)
// over the part of the cell [x0, x0+h] x [y0, y0+h] inside the unit disk: midpoint rule over
// sub-rows in y, exact along x (the function is linear in x and the disk is an interval).
double rim_mass(double x0, double y0, double h, double a, double b, double c, double d) {
  double sum = 0;
  const double dy = h / kRimRows;
  for (int k = 0; k < kRimRows; ++k) {
    const double y = y0 + (k + 0.5) * dy;
    const double s2 = 1 - y * y;
    if (s2 <= 0) continue;
    const double s = std::sqrt(s2);
    const double xa = std::max(x0, -s), xb = std::min(x0 + h, s);
    if (xb <= xa) continue;
    const double ty = (y - y0) / h, tx = (0.5 * (xa + xb) - x0) / h;
    const double f = (1 - ty) * ((1 - tx) * a + tx * b) + ty * ((1 - tx) * c + tx * d);
    sum += f * (xb - xa);
  }
  return sum * dy;
}

// Index of the interval of `cdf` (inclusive cumulative, last = 1) holding u, skipping
// zero-width intervals; writes u rescaled to [0, 1) within that interval.
std::size_t pick(const double* cdf, std::size_t n, double u, double& rescaled) {
  std::size_t i = static_cast<std::size_t>(std::upper_bound(cdf, cdf + n, u) - cdf);
  if (i >= n) i = n - 1;
  double lo = i ? cdf[i - 1] : 0.0;
  while (i > 0 && cdf[i] <= lo) {  // only reachable for u >= 1 (rounding): step back
    --i;
    lo = i ? cdf[i - 1] : 0.0;
  }
  const double w = cdf[i] - lo;
  rescaled = w > 0 ? std::clamp((u - lo) / w, 0.0, std::nextafter(1.0, 0.0)) : 0.0;
  return i;
}

}  // namespace

NdfSampler::NdfSampler(const TabulatedNdf& ndf) : ndf_(&ndf) {
  const std::size_t n = ndf.resolution();
  cells_ = n - 1;
  const double h = ndf.spacing(), area = h * h;
  row_cdf_.assign(cells_, 0.0);
  cell_cdf_.assign(cells_ * cells_, 0.0);
  double z = 0, total = 0;
  for (std::size_t cy = 0; cy < cells_; ++cy) {
    const double y0 = ndf.node_y(cy), y1 = y0 + h;
    const double ny = std::clamp(0.0, y0, y1), fy = std::max(std::fabs(y0), std::fabs(y1));
    double* row = &cell_cdf_[cy * cells_];
    double row_sum = 0;
    for (std::size_t cx = 0; cx < cells_; ++cx) {
      const double x0 = ndf.node_x(cx), x1 = x0 + h;
      const double nx = std::clamp(0.0, x0, x1), fx = std::max(std::fabs(x0), std::fabs(x1));
      double mass = 0;
      if (nx * nx + ny * ny < 1) {  // the cell meets the open disk
        const double a = ndf.at(cx, cy), b = ndf.at(cx + 1, cy);
        const double c = ndf.at(cx, cy + 1), d = ndf.at(cx + 1, cy + 1);
        mass = 0.25 * (a + b + c + d) * area;
        z += fx * fx + fy * fy <= 1 ? mass : rim_mass(x0, y0, h, a, b, c, d);
      }
      row_sum += mass;
      row[cx] = row_sum;
    }
    if (row_sum > 0)
      for (std::size_t cx = 0; cx < cells_; ++cx) row[cx] /= row_sum;
    total += row_sum;
    row_cdf_[cy] = total;
  }
  if (!(total > 0) || !(z > 0) || !std::isfinite(total))
    throw std::invalid_argument("NdfSampler: the table has no mass inside the unit disk");
  for (double& v : row_cdf_) v /= total;
  z_ = z;
}

Eigen::Vector3d NdfSampler::sample(double u1, double u2) const {
  const TabulatedNdf& t = *ndf_;
  const double h = t.spacing();
  std::size_t cx = 0, cy = 0;
  for (int attempt = 0; attempt < kMaxTries; ++attempt) {
    double v1 = 0, v2 = 0;
    cy = pick(row_cdf_.data(), cells_, u1, v1);
    cx = pick(&cell_cdf_[cy * cells_], cells_, u2, v2);
    const double a = t.at(cx, cy), b = t.at(cx + 1, cy);
    const double c = t.at(cx, cy + 1), d = t.at(cx + 1, cy + 1);
    const double ty = sample_linear(v1, 0.5 * (a + b), 0.5 * (c + d));
    const double tx = sample_linear(v2, (1 - ty) * a + ty * c, (1 - ty) * b + ty * d);
    const double x = t.node_x(cx) + tx * h, y = t.node_y(cy) + ty * h;
    const double r2 = x * x + y * y;
    if (r2 < 1) return {x, y, std::sqrt(1 - r2)};
    // Outside the disk (a cell the circle crosses): redraw from fresh numbers derived from the
    // inputs, so that sample() stays a deterministic function of (u1, u2).
    const std::uint64_t k = std::bit_cast<std::uint64_t>(u1) ^
                            std::rotl(std::bit_cast<std::uint64_t>(u2), 29) ^
                            (static_cast<std::uint64_t>(attempt + 1) << 56);
    u1 = to_unit(splitmix64(k));
    u2 = to_unit(splitmix64(k ^ 0xD1B54A32D192ED03ull));
  }
  // Pathological table (almost all proposal mass outside the disk): the centre of the last
  // cell, pulled inside the disk.
  double x = t.node_x(cx) + 0.5 * h, y = t.node_y(cy) + 0.5 * h;
  const double r = std::hypot(x, y), rmax = 1 - 1e-9;
  if (r > rmax) {
    x *= rmax / r;
    y *= rmax / r;
  }
  return {x, y, std::sqrt(std::max(0.0, 1 - x * x - y * y))};
}

double NdfSampler::pdf(const Eigen::Vector3d& m) const {
  const double len = m.norm();
  if (!(len > 0) || !(m.z() > 0)) return 0.0;
  return ndf_->eval(m) * (m.z() / len) / z_;
}

}  // namespace microbrdf
