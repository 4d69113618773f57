#pragma once
// A piecewise-constant 2D distribution over [0,1)^2 on an nu x nv grid of cells (environment-map
// importance sampling), drawn by inverting the marginal CDF over rows and then the conditional
// CDF of the chosen row. Inversion is monotone in each uniform, so the stratification of a
// low-discrepancy 2D point (path_sampler.hpp) carries over to the sphere; an alias table would be
// O(1) but scatters neighbouring points to unrelated cells.
//
// Memory layout for speed (a map's tables are megabytes, so every read is a cache miss): each CDF
// has a guide table (the cutpoint method: entry j holds the bin of the point j / m of the total,
// so a search starts next to its answer and walks about two steps on average, the entries being
// equally probable, instead of a binary search's log2(m) scattered reads; the bin found is
// exactly the binary search's). The guide tables are 16-bit and kept apart (2 bytes per cell:
// 1 MB for a 1024 x 512 map, which stays in the caches), while a row's running sum, density and
// an optional payload (the map's radiance) share one 32-byte record per cell, so that a draw
// reads the guide and then one or two cache lines of the row's records, which also hold the
// chosen cell's radiance.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "core/huge_page_allocator.hpp"

namespace microbrdf::pt {

class PiecewiseConstant2D {
 public:
  PiecewiseConstant2D() = default;
  /// f[row * nu + col] >= 0 (negative and non-finite values count as 0). All zero: uniform.
  /// `payload`, when given, holds 3 floats per cell (row-major like f), returned by payload().
  PiecewiseConstant2D(const std::vector<double>& f, std::size_t nu, std::size_t nv,
                      const float* payload = nullptr)
      : nu_(nu),
        nv_(nv),
        gu_(std::max<std::size_t>(1, nu / kColGuideStride)),
        row_cdf_(nv + 1),
        row_guide_(nv + 1),
        col_guide_((gu_ + 1) * nv),
        cells_((nu + 1) * nv) {
    if (nu > 65535) throw std::invalid_argument("PiecewiseConstant2D: at most 65535 columns");
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
    row_cdf_[0] = 0;
    std::vector<double> c(nu + 1);
    std::vector<std::uint32_t> g(nu + 1);
    for (std::size_t r = 0; r < nv; ++r) {
      c[0] = 0;
      for (std::size_t k = 0; k < nu; ++k) c[k + 1] = c[k] + w[r * nu + k];
      row_cdf_[r + 1] = row_cdf_[r] + c[nu];
      build_guide(c.data(), nu, gu_, g.data());
      for (std::size_t j = 0; j <= gu_; ++j) col_guide_[r * (gu_ + 1) + j] = std::uint16_t(g[j]);
      Cell* rc = &cells_[r * (nu + 1)];
      for (std::size_t k = 0; k <= nu; ++k) {
        rc[k].cdf = c[k];
        if (k == nu) continue;
        // Density per unit area of [0,1)^2 is w_i n / sum (mean 1).
        rc[k].density = float(w[r * nu + k] * double(n) / sum);
        if (payload)
          for (int ch = 0; ch < 3; ++ch) rc[k].payload[ch] = payload[(r * nu + k) * 3 + ch];
      }
    }
    build_guide(row_cdf_.data(), nv, nv, row_guide_.data());
  }

  /// (u, v) in [0,1)^2 from two uniforms (u1 -> column within the row, u2 -> row), with its
  /// density per unit area; returns the cell index (row * nu + col).
  std::size_t sample(double u1, double u2, double& u, double& v, double& pdf) const {
    double fv;
    const std::size_t row = invert_rows(u2, fv);
    double fu;
    const Cell* rc = &cells_[row * (nu_ + 1)];
    const std::size_t col = invert_cols(rc, &col_guide_[row * (gu_ + 1)], u1, fu);
    u = (double(col) + fu) / double(nu_);
    v = (double(row) + fv) / double(nv_);
    pdf = rc[col].density;
    return row * nu_ + col;
  }
  /// The same as (col + fu, row + fv) in cells, fu and fv in [0, 1); returns the cell's
  /// payload (read from the record the search ends on).
  const float* sample_cell(double u1, double u2, std::size_t& col, double& fu, std::size_t& row,
                           double& fv, double& pdf) const {
    row = invert_rows(u2, fv);
    const Cell* rc = &cells_[row * (nu_ + 1)];
    col = invert_cols(rc, &col_guide_[row * (gu_ + 1)], u1, fu);
    pdf = rc[col].density;
    return rc[col].payload;
  }
  /// Starts loading what sample(u1, u2, ...) reads first from memory (the guide entry of the
  /// row that u2 picks), so that the draw, made later, finds it in the cache.
  /// With `cells`, also the record the column walk starts at (reads the guide entry, which
  /// stays in the caches).
  void prefetch_sample(double u1, double u2, bool prefetch_cells = false) const {
    double fv;
    const std::size_t row = invert_rows(u2, fv);
    const double gx = u1 * double(gu_);
    const std::size_t j = gx > 0 ? std::min(std::size_t(gx), gu_) : 0;
    const std::uint16_t* guide = &col_guide_[row * (gu_ + 1)];
    __builtin_prefetch(guide + j);
    if (!prefetch_cells) return;
    // The walk ends at or before guide[j + 1] (and reads the record after it): every cache line
    // from guide[j] on, at most kColGuideStride + 2 records (longer spans are empty cells).
    const std::size_t lo = guide[j],
                      hi = std::min<std::size_t>({std::size_t(guide[std::min(j + 1, gu_)]) + 1, nu_,
                                                  lo + kColGuideStride + 1});
    const char* first = reinterpret_cast<const char*>(&cells_[row * (nu_ + 1) + lo]);
    const char* last = reinterpret_cast<const char*>(&cells_[row * (nu_ + 1) + hi]);
    for (const char* p = first; p <= last; p += 64) __builtin_prefetch(p);
  }
  /// Starts loading the record of cell (col, row).
  void prefetch_cell(std::size_t col, std::size_t row) const {
    __builtin_prefetch(&cells_[row * (nu_ + 1) + col]);
  }
  /// Density per unit area in cell (col, row).
  double pdf(std::size_t col, std::size_t row) const {
    return cells_[row * (nu_ + 1) + col].density;
  }
  /// The 3 floats given for cell (col, row) (zeros without a payload).
  const float* payload(std::size_t col, std::size_t row) const {
    return cells_[row * (nu_ + 1) + col].payload;
  }
  /// The same by the cell index sample() returns.
  const float* payload(std::size_t cell) const { return payload(cell % nu_, cell / nu_); }
  bool empty() const { return cells_.empty(); }

 private:
  struct Cell {
    double cdf = 0;     // running sum of the row's weights before this cell
    float density = 0;  // per unit area of [0,1)^2
    float payload[3] = {0, 0, 0};
    float pad[2] = {0, 0};
  };
  static_assert(sizeof(Cell) == 32, "two cells per cache line");

  // The bin k of a CDF c[0..m] (c[0] = 0) with c[k] <= x c[m] < c[k+1], skipping empty bins,
  // and the position within it in [0,1). C(k) reads c[k], G(j) the guide (build_guide).
  template <class C, class G>
  static std::size_t invert(const C& c, const G& guide, std::size_t m, std::size_t gm, double x,
                            double& frac) {
    const double cm = c(m), t = x * cm;
    // The last k with c[k] <= t (c[0] = 0 <= t), found by walking from the guide's entry; the
    // same k as std::upper_bound(c, c + m + 1, t) - c - 1 whatever the guide says.
    const double gx = x * double(gm);
    std::size_t k = guide(gx > 0 ? std::min(std::size_t(gx), gm) : 0);
    // The first 8 steps without branches (c is non-decreasing: the c[k + i] <= t are a prefix),
    // as the walk's end, a data-dependent branch, is mispredicted about once per search.
    if (k + 8 <= m) {
      std::size_t steps = 0;
      for (std::size_t i = 1; i <= 8; ++i) steps += c(k + i) <= t ? 1 : 0;
      k += steps;
    }
    while (k < m && c(k + 1) <= t) ++k;
    while (k > 0 && c(k) > t) --k;
    k = std::min(k, m - 1);
    while (k + 1 < m && !(c(k + 1) > c(k))) ++k;  // t == c[k] at an empty bin
    while (k > 0 && !(c(k + 1) > c(k))) --k;      // rounding past the last non-empty bin
    const double width = c(k + 1) - c(k);
    // Kept 1e-7 of a cell away from its edges, so that the direction built from (u, v) falls
    // back into the same pixel after rounding (a bias of 1e-7 of a pixel).
    frac = width > 0 ? std::clamp((t - c(k)) / width, 1e-7, 1 - 1e-7) : 0.5;
    return k;
  }
  std::size_t invert_rows(double x, double& frac) const {
    return invert([this](std::size_t k) { return row_cdf_[k]; },
                  [this](std::size_t j) { return std::size_t(row_guide_[j]); }, nv_, nv_, x, frac);
  }
  std::size_t invert_cols(const Cell* rc, const std::uint16_t* guide, double x,
                          double& frac) const {
    return invert([rc](std::size_t k) { return rc[k].cdf; },
                  [guide](std::size_t j) { return std::size_t(guide[j]); }, nu_, gu_, x, frac);
  }
  // guide[j], j = 0..gm: the last k with c[k] <= (j / gm) c[m] (where invert's walk starts).
  static void build_guide(const double* c, std::size_t m, std::size_t gm, std::uint32_t* guide) {
    std::size_t k = 0;
    for (std::size_t j = 0; j <= gm; ++j) {
      const double t = double(j) / double(gm) * c[m];
      while (k < m && c[k + 1] <= t) ++k;
      guide[j] = std::uint32_t(k);
    }
  }
  // Column guides have one entry per kColGuideStride cells: 128 KB for a 1024 x 512 map, which
  // stays in the caches, and the walk from an entry reads a few consecutive records (about
  // kColGuideStride / 2 on average over a row of equal cells), which the hardware streams.
  static constexpr std::size_t kColGuideStride = 8;
  std::size_t nu_ = 0, nv_ = 0, gu_ = 1;  // gu_: column guide intervals per row
  std::vector<double> row_cdf_;           // nv + 1 running sums of row weights
  std::vector<std::uint32_t> row_guide_;  // guide table of row_cdf_
  std::vector<std::uint16_t, microbrdf::detail::HugePageAllocator<std::uint16_t>>
      col_guide_;  // per row, gu + 1
  std::vector<Cell, microbrdf::detail::HugePageAllocator<Cell>>
      cells_;  // per row, nu + 1 records (last: the total)
};

}  // namespace microbrdf::pt
