// Importance sampling of a tabulated NDF, exactly consistent with TabulatedNdf::eval
// (docs/theory.md §2.4, piecewise-bilinear variant).
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
#include "microbrdf/ndf_sampler.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/bilinear_cell.hpp"

namespace microbrdf {
namespace {

using detail::cell_centre_in_disk;
using detail::pick;
using detail::redraw_uniforms;
using detail::rim_mass;
using detail::sample_bilinear;

constexpr int kMaxTries = 64;

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
    double tx = 0, ty = 0;
    sample_bilinear(v1, v2, a, b, c, d, tx, ty);
    const double x = t.node_x(cx) + tx * h, y = t.node_y(cy) + ty * h;
    const double r2 = x * x + y * y;
    if (r2 < 1) return {x, y, std::sqrt(1 - r2)};
    // Outside the disk (a cell the circle crosses): redraw from fresh numbers derived from the
    // inputs, so that sample() stays a deterministic function of (u1, u2).
    redraw_uniforms(u1, u2, attempt, 56);
  }
  // Pathological table (almost all proposal mass outside the disk): the centre of the last
  // cell, pulled inside the disk.
  return cell_centre_in_disk(t.node_x(cx), t.node_y(cy), h);
}

double NdfSampler::pdf(const Eigen::Vector3d& m) const {
  const double len = m.norm();
  if (!(len > 0) || !(m.z() > 0)) return 0.0;
  return ndf_->eval(m) * (m.z() / len) / z_;
}

}  // namespace microbrdf
