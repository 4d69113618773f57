// Internal helpers for sampling the piecewise-bilinear interpolant of a tabulated NDF on the
// unit disk, shared by NdfSampler (src/ndf/ndf_sampler.cpp) and the visible-normal tables of
// the tabulated distribution (src/models/tabulated_distribution_vn.cpp). Inline: they sit on
// the sampling hot paths.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "core/splitmix64.hpp"

namespace microbrdf::detail {

// Sub-rows per rim cell in rim_mass (exact integration along x in each; Z to ~1e-12).
inline constexpr int kRimRows = 256;

// Inverse CDF of the linear density on [0, 1] with end values p0, p1 >= 0, written so that it
// is stable for p0 ~ p1 and for either end value 0.
inline double sample_linear(double u, double p0, double p1) {
  if (p0 == p1) return u;
  const double denom = p0 + std::sqrt(p0 * p0 * (1 - u) + p1 * p1 * u);
  if (!(denom > 0)) return 0.0;
  const double t = u * (p0 + p1) / denom;
  return std::min(t, std::nextafter(1.0, 0.0));
}

// Exact sample (tx, ty) in [0, 1)^2 of the bilinear density with corner values a (0,0),
// b (1,0), c (0,1), d (1,1): marginal in y linear, conditional in x linear.
inline void sample_bilinear(double u1, double u2, double a, double b, double c, double d,
                            double& tx, double& ty) {
  ty = sample_linear(u1, 0.5 * (a + b), 0.5 * (c + d));
  tx = sample_linear(u2, (1 - ty) * a + ty * c, (1 - ty) * b + ty * d);
}

inline double to_unit(std::uint64_t h) { return static_cast<double>(h >> 11) * 0x1.0p-53; }

// Fresh uniforms for redraw number `attempt` (0-based) after a rejected point, derived from the
// current ones so that a sampler stays a deterministic function of its inputs. `shift` places
// the attempt counter in the key (each caller keeps its own, so its sample sequence is fixed).
inline void redraw_uniforms(double& u1, double& u2, int attempt, int shift) {
  const std::uint64_t k = std::bit_cast<std::uint64_t>(u1) ^
                          std::rotl(std::bit_cast<std::uint64_t>(u2), 29) ^
                          (static_cast<std::uint64_t>(attempt + 1) << shift);
  u1 = to_unit(splitmix64(k));
  u2 = to_unit(splitmix64(k ^ 0xD1B54A32D192ED03ull));
}

// Mass of the bilinear function with corner values a (x0,y0), b (x1,y0), c (x0,y1), d (x1,y1)
// over the part of the cell [x0, x0+h] x [y0, y0+h] inside the unit disk: midpoint rule over
// sub-rows in y, exact along x (the function is linear in x and the disk is an interval).
inline double rim_mass(double x0, double y0, double h, double a, double b, double c, double d) {
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

// pick's second half: from i, the count of entries <= u, the interval holding u (skipping
// zero-width intervals) and u rescaled to [0, 1) within it.
template <class T>
std::size_t pick_from_count(const T* cdf, std::size_t n, std::size_t i, double u,
                            double& rescaled) {
  if (i >= n) i = n - 1;
  double lo = i ? static_cast<double>(cdf[i - 1]) : 0.0;
  while (i > 0 && static_cast<double>(cdf[i]) <= lo) {  // u >= last entry (rounding only)
    --i;
    lo = i ? static_cast<double>(cdf[i - 1]) : 0.0;
  }
  const double w = static_cast<double>(cdf[i]) - lo;
  rescaled = w > 0 ? std::clamp((u - lo) / w, 0.0, std::nextafter(1.0, 0.0)) : 0.0;
  return i;
}

// Index i of the interval [cdf[i-1], cdf[i]) of an inclusive CDF (last entry 1) holding u in
// [0, 1), skipping zero-width intervals; writes u rescaled to [0, 1) within it.
template <class T>
std::size_t pick(const T* cdf, std::size_t n, double u, double& rescaled) {
  return pick_from_count(cdf, n, static_cast<std::size_t>(std::upper_bound(cdf, cdf + n, u) - cdf),
                         u, rescaled);
}

// Fallback point when every redraw fell outside the disk: the centre of the cell with corner
// (x0, y0) and side h, pulled just inside the unit disk, lifted onto the hemisphere.
inline Eigen::Vector3d cell_centre_in_disk(double x0, double y0, double h) {
  double x = x0 + 0.5 * h, y = y0 + 0.5 * h;
  const double r = std::hypot(x, y), rmax = 1 - 1e-9;
  if (r > rmax) {
    x *= rmax / r;
    y *= rmax / r;
  }
  return {x, y, std::sqrt(std::max(0.0, 1 - x * x - y * y))};
}

}  // namespace microbrdf::detail
