#pragma once
// Approximate visible-normal sampling of a tabulated NDF with an exact pdf (private to
// TabulatedDistribution; the method is described in tabulated_distribution.hpp and
// docs/models.md).
//
// Two levels over the node grid of the table (disk coordinates (m_x, m_y)):
//  - coarse cells (nc x nc blocks of fine cells, default 128^2 = 8 x 8 cells of a 1025 table)
//    with masses M_C = integral over C inside the disk of the bilinear interpolant;
//  - fine cells (the table's cells) inside each coarse cell, drawn with probability m_f / M_C
//    (m_f: the interpolant's mass inside the disk), then the bilinear density inside the
//    cell exactly (points outside the disk rejected and redrawn inside the same cell).
// So, given the coarse cell, m has density eval(m) / M_C on the disk: the pdf is exact for any
// coarse-cell probabilities P(C). These come from view tables: for view nodes v_k on a
// (theta, phi) grid, P_k(C) = integral_C D <v_k.m>+ dw / sigma+(v_k), the visible-normal
// probability of C, computed from slope moments of 2 x 2 sub-blocks per coarse cell (exact
// where the horizon of v_k does not cross a sub-block). For a view v the tables of the four
// surrounding nodes are mixed with bilinear weights w_k(v) and a defensive fraction eps of
// the plain D(m)(m.n) probability Q(C) = M_C / sum M is added:
//   P(C | v) = (1 - eps) sum_k w_k(v) P_k(C) + eps Q(C),
//   pdf(m | v) = P(C(m) | v) eval(m) / M_C(m) * m_z      per steradian.
// eps > 0 keeps the pdf positive wherever D > 0 (no bias when v lies between nodes and the
// horizon moved), and bounds the weights by 1/eps times those of the plain sampler.
// Coarse cells are drawn row first (u1), then within the row (u2), which keeps the
// stratification of (u1, u2) in two dimensions. The pdf uses the very CDF differences that the
// sampler's searches see, so the two agree to rounding.

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>
#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include "core/bilinear_cell.hpp"
#include "microbrdf/microfacet.hpp"
#include "microbrdf/tabulated_distribution.hpp"
#include "microbrdf/tabulated_ndf.hpp"

namespace microbrdf::detail {

// The number of entries <= u of a CDF: for a non-decreasing one, std::upper_bound's index.
// Every entry is compared (SSE2: four floats or two doubles per instruction): the loads do not
// depend on each other, so a CDF out of the caches costs about one memory latency, where the
// binary search waits for each halving step's load and mispredicts about every other branch.
inline std::size_t count_le(const float* a, std::size_t n, double u) {
  // entry <= u  <=>  entry <= the largest float <= u (entries are floats)
  float f = static_cast<float>(u);
  if (static_cast<double>(f) > u) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  std::size_t i = 0, c = 0;
#ifdef __SSE2__
  const __m128 vf = _mm_set1_ps(f);
  __m128i acc = _mm_setzero_si128();
  for (; i + 4 <= n; i += 4)  // (a true lane is -1)
    acc = _mm_sub_epi32(acc, _mm_castps_si128(_mm_cmple_ps(_mm_loadu_ps(a + i), vf)));
  alignas(16) std::uint32_t lanes[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(lanes), acc);
  c = std::size_t{lanes[0]} + lanes[1] + lanes[2] + lanes[3];
#endif
  for (; i < n; ++i) c += a[i] <= f;
  return c;
}

inline std::size_t count_le(const double* a, std::size_t n, double u) {
  std::size_t i = 0, c = 0;
#ifdef __SSE2__
  const __m128d vu = _mm_set1_pd(u);
  __m128i acc = _mm_setzero_si128();
  for (; i + 2 <= n; i += 2)
    acc = _mm_sub_epi64(acc, _mm_castpd_si128(_mm_cmple_pd(_mm_loadu_pd(a + i), vu)));
  alignas(16) std::uint64_t lanes[2];
  _mm_store_si128(reinterpret_cast<__m128i*>(lanes), acc);
  c = lanes[0] + lanes[1];
#endif
  for (; i < n; ++i) c += a[i] <= u;
  return c;
}

// detail::pick with the binary search replaced by count_le (the same index, hence the same
// numbers, for the non-decreasing CDFs these tables hold; `sorted` false: detail::pick).
template <class T>
std::size_t pick_counted(const T* cdf, std::size_t n, double u, double& rescaled, bool sorted) {
  if (!sorted || !(u == u)) return pick(cdf, n, u, rescaled);  // (NaN: as upper_bound)
  return pick_from_count(cdf, n, count_le(cdf, n, u), u, rescaled);
}

class VisibleNormalTables {
 public:
  VisibleNormalTables(const TabulatedNdf& t, std::size_t coarse, std::size_t theta_steps,
                      std::size_t phi_steps, double defensive);
  using Mix = TabulatedViewMix;
  /// u1, u2 uniform in [0,1). A unit m with m_z > 0.
  Vec3 sample(const Vec3& v, double u1, double u2) const { return sample(mix(v), u1, u2); }
  /// The same for x = view_mix(v).
  Vec3 sample(const Mix& x, double u1, double u2) const;
  /// Density of sample(v, ...) per steradian of m.
  double pdf(const Vec3& v, const Vec3& m) const;
  /// The same from the view's mix and pdf's own table look-up: e = eval_disk(m_x/|m|, m_y/|m|)
  /// > 0 in cell (cx, cy), mz = m_z / |m|.
  double pdf_at(const Mix& x, std::size_t cx, std::size_t cy, double e, double mz) const {
    const std::size_t c = coarse_of(cx, cy);
    if (!(mass_[c] > 0)) return 0.0;
    return coarse_probability(x, c) * e / mass_[c] * mz;
  }
  /// Hints the memory pdf_at(x, cx, cy, ...) reads.
  void prefetch(const Mix& x, std::size_t cx, std::size_t cy) const;
  /// The view tables' weights for v (the memo-free mix).
  Mix view_mix(const Vec3& v) const { return mix_uncached(v); }
  /// Sum of the interpolant's masses inside the disk (Z).
  double total_mass() const { return total_; }
  std::size_t memory_bytes() const;
  std::size_t coarse() const { return nc_; }

 private:
  std::size_t coarse_of(std::size_t cx, std::size_t cy) const {
    return (cy * nc_ / cells_) * nc_ + cx * nc_ / cells_;
  }
  Mix mix(const Vec3& v) const;  // with a per-thread memo of the last v
  Mix mix_uncached(const Vec3& v) const;
  double coarse_probability(const Mix& x, std::size_t c) const;

  const TabulatedNdf* t_;
  std::uint64_t id_ = next_id();  // never 0, unique per object (the mix memo's key)
  static std::uint64_t next_id() {
    static std::atomic<std::uint64_t> n{0};
    return ++n;
  }
  std::size_t cells_ = 0, nc_ = 0, nt_ = 0, np_ = 0;
  double eps_ = 0.05, total_ = 0;
  std::vector<double> fine_cdf_;        // per coarse cell, inclusive, normalised to 1
  std::vector<std::uint32_t> fine_id_;  // fine cell index cy * cells + cx, same order
  std::vector<std::uint32_t> offset_;   // coarse cell -> first entry in fine_*, nc^2 + 1
  std::vector<double> mass_;            // M_C
  // Coarse cells are drawn as a row (u1) and then a cell of the row (u2), which keeps the
  // stratification of (u1, u2) in two dimensions. Each CDF block (block_ entries): nc row CDF
  // entries, then per row r the conditional CDF over its cells row_lo_[r], row_lo_[r] + 1, ...
  // (the span of the row's cells with mass M_C > 0; no table gives mass outside it) at
  // nc + row_off_[r], all inclusive, last = 1.
  std::vector<std::uint32_t> row_lo_, row_off_;  // nc and nc + 1 entries
  std::size_t block_ = 0;
  bool sorted_ = false;  // every CDF non-decreasing (the samplers may count instead of search)
  std::vector<double> q_cdf_;  // defensive: M_C / total
  // (nt + 1) * np view tables, block_ entries each, in float: they only choose the coarse
  // cell, and the pdf uses the very same (float) CDF differences, so it stays exact; half the
  // bytes of double tables halves the cache misses of the searches and density reads.
  std::vector<float> view_cdf_;
};

}  // namespace microbrdf::detail
