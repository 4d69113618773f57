// Kirchhoff distribution on the full N x N table at fixed lambda_q, fast (docs/theory.md §4.3).
//
// On the table q = |q| (m_x, m_y, m_z) and q_z = |q| m_z runs over [0, |q|]. Write
// q_z = q_c + r t, q_c = r = |q|/2, t in [-1, 1], and h' = h - h_c (h_c the middle of the height
// range, H its half-width). Jacobi-Anger gives, exactly,
//   exp(-i q_z h') = exp(-i q_c h') sum_n c_n(r h') T_n(t),  c_0 = J_0, c_n = 2 (-i)^n J_n,
// and q_z exp(-i q_z h') has the coefficients q_c C_n + r S_n (t T_n = (T_{n+1} + T_{|n-1|})/2).
// |J_n(r h')| <= |J_n(r H)| for n >= r H, so the series is cut where 2 sum |J_n(r H)| < accuracy.
// Per term n the three sample arrays
//   A_n = w (q_c C_n + r S_n),  B_n = w g_x C_n,  C_n' = w g_y C_n   (times dx dy)
// go through a transform along x at the nodes' q_x (a type-2 NUFFT, or a chirp-z transform),
// A_n - q_x B_n and C_n' through one along y, and I_n = Y[A_n - q_x B_n] - q_y Y[C_n'];
// I(q) = sum_n I_n T_n(t(q)) by Clenshaw. The global phase exp(-i q_z h_c) and the patch origin
// are dropped (|I| is unchanged). The transforms are kirchhoff_transform.hpp; how the work is cut
// into blocks and threads is said where the passes are (table_fast) and in docs/kirchhoff.md.
#include <omp.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <mutex>
#include <stdexcept>

#include "core/fft.hpp"
#include "core/helper_pool.hpp"
#include "core/length_text.hpp"
#include "core/simd_clones.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/kirchhoff.hpp"
#include "microbrdf/memory_budget.hpp"
#include "ndf/kirchhoff_transform.hpp"

namespace microbrdf {
namespace {

using cd = std::complex<double>;

// J_n(z) for n = 0..nmax, z in [0, zmax], by cubic Hermite interpolation of a table (spacing
// 1/32, derivatives from J_n' = (J_{n-1} - J_{n+1})/2): error < 3e-9.
class BesselTable {
 public:
  BesselTable(std::size_t nmax, double zmax) {
    npts_ = static_cast<std::size_t>(std::ceil(zmax * kInvStep)) + 2;
    last_ = static_cast<long>(npts_) - 2;
    tab_.assign((nmax + 1) * npts_ * 2, 0.0);
    for (std::size_t i = 0; i < npts_; ++i) {
      auto j = bessel_j_all(nmax + 1, static_cast<double>(i) / kInvStep);
      for (std::size_t n = 0; n <= nmax; ++n) {
        tab_[2 * (n * npts_ + i)] = j[n];
        tab_[2 * (n * npts_ + i) + 1] = (n == 0 ? -j[1] : 0.5 * (j[n - 1] - j[n + 1])) / kInvStep;
      }
    }
  }
  double operator()(std::size_t n, double z) const {  // z >= 0
    const double f = z * kInvStep;
    // A signed conversion (one instruction; an unsigned one is not on x86-64 before AVX-512).
    const auto i = static_cast<std::size_t>(std::min(static_cast<long>(f), last_));
    const double u = f - static_cast<double>(i);
    const double* v = &tab_[2 * (n * npts_ + i)];  // J, step J' at i; then at i + 1
    const double u2 = u * u, u3 = u2 * u;
    return (2 * u3 - 3 * u2 + 1) * v[0] + (u3 - 2 * u2 + u) * v[1] + (-2 * u3 + 3 * u2) * v[2] +
           (u3 - u2) * v[3];
  }

 private:
  static constexpr double kInvStep = 32;  // table spacing 1/32
  std::size_t npts_ = 0;
  long last_ = 0;            // npts_ - 2, the last interval
  std::vector<double> tab_;  // per order and point: J_n, step J_n'
};

}  // namespace

namespace {

// One position of the triangle rule: cell coordinates (a, b) in [0, 1]^2 of a point of the
// lower (family 0: b <= a) or upper (family 1: a <= b) triangle of every cell, and its weight
// (the weights of one family sum to 1/2, the triangle's area in cell units).
struct RulePoint {
  double a, b, weight;
};

// Collapsed (Duffy) Gauss-Legendre rule, pu points along the collapsed direction and pv across,
// grouped by b (points of one group share their y offset, hence one y-pass).
std::vector<std::vector<RulePoint>> triangle_rule(int family, std::size_t pu, std::size_t pv) {
  std::vector<double> xu, wu, xv, wv;
  detail::gauss_legendre01(pu, xu, wu);
  detail::gauss_legendre01(pv, xv, wv);
  std::vector<std::vector<RulePoint>> groups(pv);
  for (std::size_t j = 0; j < pv; ++j)
    for (std::size_t i = 0; i < pu; ++i) {
      const double v = xv[j], u = xu[i];
      if (family == 0)  // b = v, a in [v, 1]
        groups[j].push_back({v + (1 - v) * u, v, wu[i] * wv[j] * (1 - v)});
      else  // b = v, a in [0, v]
        groups[j].push_back({v * u, v, wu[i] * wv[j] * v});
    }
  return groups;
}

// Relative error of the p-point Gauss-Legendre rule for exp(i w t) on [0, 1], |w| <= span:
// (p!)^4 / ((2p + 1) ((2p)!)^3) span^(2p).
double gauss_error(std::size_t p, double span) {
  double lg = 4 * std::lgamma(static_cast<double>(p) + 1) -
              std::log(2.0 * static_cast<double>(p) + 1) -
              3 * std::lgamma(2.0 * static_cast<double>(p) + 1) +
              2.0 * static_cast<double>(p) * std::log(std::max(span, 1e-300));
  return std::exp(lg);
}

using detail::AlignedArray;
using detail::KirchhoffAxis;

typedef double V4 __attribute__((vector_size(32), may_alias));

constexpr std::size_t kRows = 2;        // sample rows per x-block
constexpr std::size_t kVx = 3 * kRows;  // x-vectors per block: A, B, C of each row
constexpr std::size_t kCols = 2;        // node columns per y-block
constexpr std::size_t kVy = 2 * kCols;  // y-vectors per block: A - q_x B and C of each column
constexpr std::size_t kMaxBatch = 4;    // terms per pass over the Clenshaw state

// out[(k - k0) V + v] = sum_t w[k K + t] bins[v ld + start[k] + t] for k in [k0, k1): the K-tap
// sums of V complex vectors (K even: the taps are taken in pairs, one pair per V4; V even; out
// 32-byte aligned).
typedef double V4u __attribute__((vector_size(32), aligned(8), may_alias));
typedef long long V4i __attribute__((vector_size(32)));

template <std::size_t V>
[[gnu::always_inline]] inline void tap_sums_body(const double* __restrict w,
                                                 const std::size_t* __restrict start, std::size_t K,
                                                 std::size_t k0, std::size_t k1, const cd* bins,
                                                 std::size_t ld, cd* out) {
  const double* bd = reinterpret_cast<const double*>(bins);
  double* od = reinterpret_cast<double*>(out);
  for (std::size_t k = k0; k < k1; ++k) {
    const double* wk = w + k * K;
    const double* b0 = bd + 2 * start[k];
    V4 acc[V];
    for (std::size_t v = 0; v < V; ++v) acc[v] = V4{0, 0, 0, 0};
    for (std::size_t t = 0; t < K; t += 2) {
      const V4 wt = {wk[t], wk[t], wk[t + 1], wk[t + 1]};
      for (std::size_t v = 0; v < V; ++v)
        acc[v] += wt * *reinterpret_cast<const V4u*>(b0 + 2 * (v * ld + t));
    }
    // Two vectors' sums per V4: [re, im] of the even taps plus those of the odd taps.
    V4* o = reinterpret_cast<V4*>(od + 2 * (k - k0) * V);
    for (std::size_t v = 0; v < V; v += 2) {
#if defined(__clang__)  // the fuzz preset builds with clang, which spells the shuffle so
      const V4 lo = __builtin_shufflevector(acc[v], acc[v + 1], 0, 1, 4, 5),
               hi = __builtin_shufflevector(acc[v], acc[v + 1], 2, 3, 6, 7);
#else
      const V4 lo = __builtin_shuffle(acc[v], acc[v + 1], V4i{0, 1, 4, 5}),
               hi = __builtin_shuffle(acc[v], acc[v + 1], V4i{2, 3, 6, 7});
#endif
      o[v / 2] = lo + hi;
    }
  }
}

MICROBRDF_SIMD_CLONES
void tap_sums_x(const double* w, const std::size_t* start, std::size_t K, std::size_t k0,
                std::size_t k1, const cd* bins, std::size_t ld, cd* out) {
  tap_sums_body<kVx>(w, start, K, k0, k1, bins, ld, out);
}

MICROBRDF_SIMD_CLONES
void tap_sums_y(const double* w, const std::size_t* start, std::size_t K, std::size_t k0,
                std::size_t k1, const cd* bins, std::size_t ld, cd* out) {
  tap_sums_body<kVy>(w, start, K, k0, k1, bins, ld, out);
}

// Stores that bypass the cache (the x-output is read back only after the whole pass, from
// memory either way: no read for ownership); stream_fence() orders them before the block ends.
#if defined(__SSE2__)
inline void stream(cd* d, cd v) {
  _mm_stream_pd(reinterpret_cast<double*>(d), _mm_set_pd(v.imag(), v.real()));
}
inline void stream_fence() { _mm_sfence(); }
#else
inline void stream(cd* d, cd v) { *d = v; }
inline void stream_fence() {}
#endif

// a b, written out (std::complex's operator* checks for NaN and Inf per product).
inline cd mul(cd a, cd b) {
  return {a.real() * b.real() - a.imag() * b.imag(), a.real() * b.imag() + a.imag() * b.real()};
}

// z (-i)^n
inline cd rotate(cd z, std::size_t n) {
  switch (n & 3) {
    case 0:
      return z;
    case 1:
      return {z.imag(), -z.real()};
    case 2:
      return -z;
    default:
      return {-z.imag(), z.real()};
  }
}

// The nodes of an N x N table inside the unit disk, packed column by column: column k holds the
// rows [lo, hi), from offset off. Their t = 2 m_z - 1 (q_z = q_c + r t) is node_t(), computed
// where it is used rather than stored (6.6 MB for N = 1025, against one square root per node
// and pass).
struct NodeLayout {
  std::size_t n = 0, count = 0;
  double d = 0;  // node spacing 2 / (N - 1)
  std::vector<std::size_t> lo, hi, off;
};

// m_x^2 + m_y^2 of node (k, l) (< 1 inside the disk); the one formula for the layout and for t.
inline double node_rr(const NodeLayout& lay, std::size_t k, std::size_t l) {
  const double mx = -1.0 + lay.d * static_cast<double>(k),
               my = -1.0 + lay.d * static_cast<double>(l);
  return mx * mx + my * my;
}
inline double node_t(const NodeLayout& lay, std::size_t k, std::size_t l) {
  return 2 * std::sqrt(1 - node_rr(lay, k, l)) - 1;
}

std::shared_ptr<const NodeLayout> node_layout(std::size_t n) {
  static std::mutex m;
  static std::shared_ptr<const NodeLayout> last;
  std::lock_guard<std::mutex> lock(m);
  if (last && last->n == n) return last;
  auto l = std::make_shared<NodeLayout>();
  l->n = n;
  l->d = 2.0 / static_cast<double>(n - 1);
  l->lo.assign(n, 0);
  l->hi.assign(n, 0);
  l->off.assign(n, 0);
  std::size_t count = 0;
  for (std::size_t k = 0; k < n; ++k) {
    l->off[k] = count;
    bool in = false;
    std::size_t inside = 0;
    for (std::size_t r = 0; r < n; ++r) {
      if (!(node_rr(*l, k, r) < 1)) continue;  // the same test as kirchhoff_node_q
      if (!in) l->lo[k] = r;
      in = true;
      l->hi[k] = r + 1;
      ++inside;
    }
    count += inside;
    if (in && inside != l->hi[k] - l->lo[k])
      throw std::logic_error("Kirchhoff: the disk is not convex along a column");
  }
  l->count = count;
  last = l;
  return last;
}

// The large arrays of one table, kept between calls (no fresh pages per table).
struct Workspace {
  AlignedArray<cd> xo;     // x-pass output per batch slot: (k ny + y) 2 + {0: A - q_x B, 1: C}
  AlignedArray<cd> state;  // Clenshaw b_{n+1}, b_{n+2} per packed node
  AlignedArray<cd> it;     // exact: sums over the rule groups of the batch's terms, per packed node
  AlignedArray<cd> pre;    // midpoint: w dA (axis factors) exp(-i q_c h') per sample
  AlignedArray<double> ring;  // midpoint: J_k(r h') of the last three orders, slot k mod 3
};

struct WorkspaceSlot {
  std::mutex m;
  std::unique_ptr<Workspace> ws;
};

WorkspaceSlot& workspace_slot() {
  static auto* s = new WorkspaceSlot;  // never destroyed
  return *s;
}

std::unique_ptr<Workspace> take_workspace() {
  auto& s = workspace_slot();
  std::lock_guard<std::mutex> lock(s.m);
  if (s.ws) return std::move(s.ws);
  return std::make_unique<Workspace>();
}

void give_workspace(std::unique_ptr<Workspace> w) {
  auto& s = workspace_slot();
  std::lock_guard<std::mutex> lock(s.m);
  if (!s.ws) s.ws = std::move(w);
}

}  // namespace

void kirchhoff_release_buffers() {
  auto& s = workspace_slot();
  std::lock_guard<std::mutex> lock(s.m);
  s.ws.reset();
}

namespace {

struct ThreadScratch {
  KirchhoffAxis::Scratch x, y;
  AlignedArray<cd> sums;      // tap sums of one block (x: N x kVx; y: batch x N x kVy)
  AlignedArray<cd> xacc;      // exact: sums over a group's points, batch x N x 2 per row
  AlignedArray<cd> rowpre;    // exact: the rule point's factor per sample of the block's rows
  AlignedArray<double> rowj;  // exact: its J of the batch's orders per sample of those rows
};

ThreadScratch& thread_scratch() {
  thread_local ThreadScratch s;
  return s;
}

// One sample row of the midpoint rule's term n into the x-block input (element x of the three
// vectors at oa, ob, oc [pos[x]]): A = pre (q_c c + i r (J_{n-1} - J_{n+1})), B = pre g_x c,
// C = pre g_y c with c = (n ? 2 : 1) J_n, the factor (-i)^n left out. Stores J_{n-1} in jm
// (n >= 1).
// The row's heights, slopes and window weights are the patch's own (h, gx, gy, w): z = r (h - h_c)
// and the slopes are taken where w != 0 and 0 elsewhere (no per-sample copies of them).
void fill_row_midpoint(std::size_t nx, std::size_t n, const BesselTable& bt, const cd* pre,
                       const double* h, const double* gx, const double* gy, const double* w,
                       double hc, const double* jp, const double* jn, double* jm, double qc,
                       double r, const std::size_t* pos, cd* oa, cd* ob, cd* oc) {
  const double alpha = n ? 2.0 : 1.0;
  for (std::size_t x = 0; x < nx; ++x) {
    const bool live = w[x] != 0;
    double m = 0;
    if (n >= 1) {
      const double zz = live ? r * (h[x] - hc) : 0.0, j = bt(n - 1, std::fabs(zz));
      m = zz < 0 && ((n - 1) & 1) ? -j : j;
      jm[x] = m;
    }
    const double u = alpha * jn[x], d = r * (m - jp[x]);
    const cd P = pre[x];
    const std::size_t q = pos[x];
    oa[q] = cd(P.real() * qc * u - P.imag() * d, P.imag() * qc * u + P.real() * d);
    ob[q] = P * ((live ? gx[x] : 0.0) * u);
    oc[q] = P * ((live ? gy[x] : 0.0) * u);
  }
}

// The Bessel series of a patch whose heights span `range` (zmax = pi range / lambda_q radians of
// phase): about zmax terms, each tabulated at 32 zmax points (BesselTable), so its memory grows
// as the square of the height range in wavelengths. An unlevelled form or a wrong z unit asks for
// terabytes: refused against the memory budget before anything is allocated.
void check_series_memory(double zmax, double range, double lambda_q) {
  const double terms = zmax + 10 * std::cbrt(zmax + 1) + 42;
  const double bytes = terms * (32 * zmax + 3) * 2 * sizeof(double);
  if (bytes <= static_cast<double>(memory_budget())) return;
  char b[320];
  std::snprintf(
      b, sizeof b,
      "Kirchhoff: the heights of a patch span %s, %.3g wavelengths (lambda_q %s): its "
      "series needs about %s, over the memory budget of %s (--max-memory); level the "
      "scan (--level plane) or check its height unit",
      detail::format_length_any(range).c_str(), range / lambda_q,
      detail::format_length_any(lambda_q).c_str(),
      bytes >= 1.8e19 ? "over 16 EiB" : format_bytes(static_cast<std::uint64_t>(bytes)).c_str(),
      format_bytes(memory_budget()).c_str());
  throw InputError(b);
}

std::vector<double> table_fast(const KirchhoffPatch& p, double lambda_q, std::size_t resolution,
                               double accuracy, KirchhoffFastInfo* info, bool chirp_z,
                               KirchhoffIntegration method, double band_x, double band_y,
                               std::vector<std::complex<double>>* amplitude) {
  if (!(lambda_q > 0)) throw InputError("Kirchhoff: lambda_q must be > 0");
  if (resolution < 3) throw InputError("Kirchhoff: resolution must be >= 3");
  if (!(accuracy > 0 && accuracy < 1)) throw InputError("Kirchhoff: accuracy must be in (0, 1)");
  const bool exact = method == KirchhoffIntegration::Exact;
  const std::size_t N = resolution;
  std::vector<double> out(N * N, 0.0);
  if (amplitude) amplitude->assign(N * N, cd(0));
  const double area = kirchhoff_area_w2(p, method);
  if (!(area > 0)) return out;
  // The transforms run over the samples (midpoint) or the cells (exact: one rule point each).
  const std::size_t nx = exact ? p.nx - 1 : p.nx, ny = exact ? p.ny - 1 : p.ny;
  if (nx == 0 || ny == 0) return out;

  const double qmag = 4 * M_PI / lambda_q, delta = 2.0 / static_cast<double>(N - 1);
  const double qc = 0.5 * qmag, r = 0.5 * qmag;
  double hmin = INFINITY, hmax = -INFINITY;
  for (std::size_t i = 0; i < p.h.size(); ++i)
    if (p.w[i] != 0) {
      hmin = std::min(hmin, p.h[i]);
      hmax = std::max(hmax, p.h[i]);
    }
  const double hc = 0.5 * (hmin + hmax), H = 0.5 * (hmax - hmin), zmax = r * H;

  check_series_memory(zmax, hmax - hmin, lambda_q);

  // Number of terms: the smallest count whose dropped tail 2 sum_{n >= terms} |J_n(zmax)| is
  // below `accuracy` (terms >= zmax, where |J_n| grows monotonically in z up to zmax).
  std::size_t guess = static_cast<std::size_t>(zmax + 10 * std::cbrt(zmax + 1) + 40);
  auto jz = bessel_j_all(guess, zmax);
  std::size_t terms = 1;
  double tail = 0;
  for (std::size_t n = guess; n >= 1; --n) {
    double t = tail + 2 * std::fabs(jz[n]);
    if (t > accuracy || static_cast<double>(n) < zmax) {
      terms = n + 1;
      break;
    }
    tail = t;
  }
  // The q_z factor makes the A series one degree longer (q_z T_{terms-1} has a T_terms part).
  ++terms;
  const BesselTable bt(terms, zmax);
  auto bessel = [&bt](std::size_t k, double z) {  // J_k(z), any sign of z
    const double j = bt(k, std::fabs(z));
    return z < 0 && (k & 1) ? -j : j;
  };

  // Per-family cell data of the triangles (exact): height relative to h_c at the cell origin,
  // height steps along a and b (slope x spacing), slopes and the window weight (0 = no triangle).
  const std::size_t ns = nx * ny;
  struct Family {
    std::vector<double> h0, sa, sb, gx, gy, w;
  };
  std::vector<Family> fam(exact ? 2 : 1);
  double longest = 0;  // largest phase span of a valid triangle's edge, rad
  const double bx = std::min(qmag, band_x), by = std::min(qmag, band_y);
  if (exact) {
    for (auto& f : fam) {
      f.h0.assign(ns, 0.0);
      f.gx.assign(ns, 0.0);
      f.gy.assign(ns, 0.0);
      f.w.assign(ns, 0.0);
      f.sa.assign(ns, 0.0);
      f.sb.assign(ns, 0.0);
    }
    for (std::size_t y = 0; y < ny; ++y)
      for (std::size_t x = 0; x < nx; ++x) {
        const std::size_t c = y * nx + x, i00 = y * p.nx + x, i10 = i00 + 1, i01 = i00 + p.nx,
                          i11 = i01 + 1;
        if (p.w[i00] == 0 || p.w[i11] == 0) continue;
        const double h00 = p.h[i00], h11 = p.h[i11];
        for (int k = 0; k < 2; ++k) {
          const std::size_t i3 = k == 0 ? i10 : i01;  // lower (00,10,11), upper (00,11,01)
          if (p.w[i3] == 0) continue;
          const double h3 = p.h[i3];
          const double sa = k == 0 ? h3 - h00 : h11 - h3, sb = k == 0 ? h11 - h3 : h3 - h00;
          Family& f = fam[static_cast<std::size_t>(k)];
          f.h0[c] = h00 - hc;
          f.sa[c] = sa;
          f.sb[c] = sb;
          f.gx[c] = sa / p.dx;
          f.gy[c] = sb / p.dy;
          f.w[c] = (p.w[i00] + p.w[i11] + p.w[i3]) / 3;
          // Largest phase difference along an edge over the nodes that count: |q| x its
          // length, or with |q_x| <= bx, |q_y| <= by (a band mask) bx |dx| + by |dy| + |q| |dh|.
          const double d11 = std::fabs(h11 - h00);
          const double ea = std::min(qmag * std::hypot(p.dx, sa), bx * p.dx + qmag * std::fabs(sa)),
                       eb = std::min(qmag * std::hypot(p.dy, sb), by * p.dy + qmag * std::fabs(sb)),
                       ed = std::min(qmag * std::sqrt(p.dx * p.dx + p.dy * p.dy + d11 * d11),
                                     bx * p.dx + by * p.dy + qmag * d11);
          longest = std::max({longest, ea, eb, ed});
        }
      }
  }
  // Rule: one point at the sample (midpoint), or per triangle a collapsed Gauss-Legendre rule
  // whose error for the largest phase span along an edge is below accuracy / 100.
  const double span = longest;
  std::size_t pu = 1;
  if (exact)
    while (pu < 40 && gauss_error(pu, span) > accuracy * 1e-2) ++pu;
  const std::size_t pv = exact ? pu + 1 : 1;
  std::vector<std::vector<std::vector<RulePoint>>> rules(fam.size());
  for (std::size_t f = 0; f < fam.size(); ++f)
    rules[f] = exact ? triangle_rule(static_cast<int>(f), pu, pv)
                     : std::vector<std::vector<RulePoint>>{{{0.0, 0.0, 1.0}}};
  if (info) {
    info->terms = terms;
    info->height_half_range = H;
    info->z_max = zmax;
    info->tail_bound = tail;
    info->points_per_triangle = pu * pv;
    info->phase_span = span;
  }

  // Transforms (cached): exact chirp-z, or the NUFFT with taps for accuracy / 100 relative to
  // sum |x|. The node frequencies are q_x = q_y = |q| (-1 + delta k).
  const auto kind = chirp_z ? KirchhoffAxis::Kind::ChirpZ : KirchhoffAxis::Kind::Nufft;
  const int taps = detail::KirchhoffAxis::taps_for(accuracy * 1e-2);
  const auto axp = KirchhoffAxis::get(kind, nx, N, -qmag * p.dx, qmag * delta * p.dx, taps, kVx);
  const auto ayp = KirchhoffAxis::get(kind, ny, N, -qmag * p.dy, qmag * delta * p.dy, taps, kVy);
  const KirchhoffAxis& ax = *axp;
  const KirchhoffAxis& ay = *ayp;
  const auto layp = node_layout(N);
  const NodeLayout& lay = *layp;
  std::vector<double> qx(N);
  for (std::size_t k = 0; k < N; ++k) qx[k] = qmag * (-1.0 + delta * static_cast<double>(k));
  const std::vector<double>& qy = qx;

  // Shifts of the rule points (exact): a phase per q_x of each point, per q_y of each group.
  std::vector<std::vector<std::vector<cd>>> xshift(fam.size()), yshift(fam.size());
  if (exact)
    for (std::size_t f = 0; f < fam.size(); ++f) {
      xshift[f].resize(rules[f].size());
      yshift[f].resize(rules[f].size());
      for (std::size_t g = 0; g < rules[f].size(); ++g) {
        const double oy = rules[f][g].front().b * p.dy;
        yshift[f][g].resize(N);
        for (std::size_t l = 0; l < N; ++l) yshift[f][g][l] = std::polar(1.0, -qy[l] * oy);
        xshift[f][g].resize(rules[f][g].size() * N);
        for (std::size_t pt = 0; pt < rules[f][g].size(); ++pt) {
          const double ox = rules[f][g][pt].a * p.dx;
          for (std::size_t k = 0; k < N; ++k)
            xshift[f][g][pt * N + k] = std::polar(1.0, -qx[k] * ox);
        }
      }
    }

  // Terms per pass over the Clenshaw state (the exact rule sums its groups per term first): as
  // many as kMaxBatch copies of the x-output within a budget allow. Midpoint: 16 MiB (one term
  // per pass on a 640 x 480 tile, 48 MB less at the peak than four, at the same wall time,
  // measured). Exact: 64 MiB, because the terms of a pass share each rule point's sincos and
  // Bessel values, its dominant cost.
  const std::size_t slot = N * ny * 2;
  const std::size_t budget = (exact ? std::size_t{64} : std::size_t{16}) << 20;
  const std::size_t batch = std::clamp<std::size_t>(budget / (slot * sizeof(cd)), 1, kMaxBatch);
  std::unique_ptr<Workspace> wsp = take_workspace();
  Workspace& ws = *wsp;
  ws.xo.resize(batch * slot);
  ws.state.resize(2 * lay.count);
  if (exact) ws.it.resize(batch * lay.count);
  if (!exact) {
    ws.pre.resize(ns);
    ws.ring.resize(3 * ns);
  }
  const bool big = ns + N * N > (1u << 17);  // threads only pay off on large problems
  const int threads = big ? std::max(1, omp_get_max_threads()) : 1;
  const double dA = p.dx * p.dy, norm = 1.0 / (4 * M_PI * M_PI * area);
  const std::size_t xblocks = (ny + kRows - 1) / kRows, yblocks = (N + kCols - 1) / kCols;
  std::size_t groups = 0;
  for (const auto& rl : rules) groups += rl.size();
  auto& pool = detail::HelperPool::instance();

  // Midpoint: per sample the factor pre = w dA (axis factors) exp(-i q_c h') and J of the two
  // highest orders (the others follow one order per term; z and the slopes are read from the
  // patch as each term fills its rows).
  if (!exact) {
    const std::function<void(std::size_t)> prepare_rows = [&](std::size_t y) {
      const cd fy = ay.factor(y);
      for (std::size_t x = 0; x < nx; ++x) {
        const std::size_t i = y * nx + x;
        double* ring = ws.ring.data();
        if (p.w[i] == 0) {
          ws.pre[i] = 0.0;
          ring[(terms % 3) * ns + i] = ring[((terms - 1) % 3) * ns + i] = 0;
          continue;
        }
        const double hp = p.h[i] - hc, z = r * hp;
        ws.pre[i] = mul(p.w[i] * dA * ax.factor(x), fy) * std::polar(1.0, -qc * hp);
        ring[(terms % 3) * ns + i] = bessel(terms, z);
        ring[((terms - 1) % 3) * ns + i] = bessel(terms - 1, z);
      }
    };
    pool.run(ny, threads, prepare_rows);
  }

  // Per term n (from the highest): the sample arrays A, B, C of every rule point, through the
  // x-transform (combined per node column into A - q_x B and C, summed over a group's points),
  // through the y-transform (combined into I_n = Y[A - q_x B] - q_y Y[C], summed over the
  // groups) and into the Clenshaw recurrence b_n = I_n + 2 t b_{n+1} - b_{n+2} per node.
  // Every block of rows or columns is computed the same way by whichever thread takes it.
  std::size_t f = 0, g = 0, gi = 0;
  std::size_t n_hi = 0, nb = 1;  // the batch: terms n_hi, n_hi - 1, ..., n_hi - nb + 1
  bool first = true;
  const std::function<void(std::size_t)> xblock = [&](std::size_t b) {  // midpoint rule
    ThreadScratch& sc = thread_scratch();
    ax.prepare(sc.x);
    sc.sums.resize(N * std::max(kVx, batch * kVy));
    cd* in = sc.x.in.data();
    const std::size_t y0 = b * kRows, K = ax.taps(), ldi = ax.in_stride();
    // The batch's terms one after the other: the block's samples stay in cache between them.
    for (std::size_t bs = 0; bs < nb; ++bs) {
      const std::size_t n = n_hi - bs;
      cd* xo = ws.xo.data() + bs * slot;
      for (std::size_t rr = 0; rr < kRows; ++rr) {
        const std::size_t y = y0 + rr;
        cd* oa = in + 3 * rr * ldi;
        cd* ob = oa + ldi;
        cd* oc = ob + ldi;
        if (y >= ny) {
          for (std::size_t x = 0; x < nx; ++x) {
            const std::size_t q = ax.position(x);
            oa[q] = ob[q] = oc[q] = 0.0;
          }
          continue;
        }
        const std::size_t i = y * nx;
        double* ring = ws.ring.data();
        fill_row_midpoint(nx, n, bt, ws.pre.data() + i, p.h.data() + i, p.gx.data() + i,
                          p.gy.data() + i, p.w.data() + i, hc, ring + ((n + 1) % 3) * ns + i,
                          ring + (n % 3) * ns + i, n >= 1 ? ring + ((n - 1) % 3) * ns + i : nullptr,
                          qc, r, ax.positions(), oa, ob, oc);
      }
      ax.run(sc.x);
      cd* sums = sc.sums.data();
      tap_sums_x(ax.weights(), ax.starts(), K, 0, N, sc.x.out.data(), ax.out_stride(), sums);
      for (std::size_t k = 0; k < N; ++k) {
        const cd* a = sums + k * kVx;
        cd* o = xo + (k * ny + y0) * 2;
        for (std::size_t rr = 0; rr < kRows && y0 + rr < ny; ++rr) {
          stream(o + 2 * rr, a[3 * rr] - qx[k] * a[3 * rr + 1]);
          stream(o + 2 * rr + 1, a[3 * rr + 2]);
        }
      }
    }
    stream_fence();
  };

  // Exact rule, one group (f, g): per rule point the factor and the Bessel values of every
  // sample are computed once for the batch's terms, then each term's arrays go through the
  // x-transform and are summed over the group's points with the points' x shifts.
  const std::function<void(std::size_t)> xblock_exact = [&](std::size_t b) {
    ThreadScratch& sc = thread_scratch();
    ax.prepare(sc.x);
    sc.sums.resize(N * std::max(kVx, batch * kVy));
    sc.xacc.resize(nb * N * 2 * kRows);
    const std::size_t orders = nb + 2;  // J of orders n_hi + 1 down to n_hi - nb
    sc.rowpre.resize(kRows * nx);
    sc.rowj.resize(kRows * orders * nx);
    cd* in = sc.x.in.data();
    const std::size_t y0 = b * kRows, K = ax.taps(), ldi = ax.in_stride();
    const auto& group = rules[f][g];
    const Family& F = fam[f];
    for (std::size_t pt = 0; pt < group.size(); ++pt) {
      const RulePoint& rp = group[pt];
      for (std::size_t rr = 0; rr < kRows && y0 + rr < ny; ++rr) {
        const std::size_t y = y0 + rr;
        const cd fy = ay.factor(y);
        cd* pre = sc.rowpre.data() + rr * nx;
        double* jr = sc.rowj.data() + rr * orders * nx;
        for (std::size_t x = 0; x < nx; ++x) {
          const std::size_t i = y * nx + x;
          if (F.w[i] == 0) {
            pre[x] = 0.0;
            for (std::size_t o = 0; o < orders; ++o) jr[o * nx + x] = 0;
            continue;
          }
          const double hp = F.h0[i] + rp.a * F.sa[i] + rp.b * F.sb[i], z = r * hp;
          pre[x] = mul(mul(F.w[i] * rp.weight * dA * ax.factor(x), fy), std::polar(1.0, -qc * hp));
          for (std::size_t o = 0; o < orders; ++o)
            jr[o * nx + x] = o <= n_hi + 1 ? bessel(n_hi + 1 - o, z) : 0.0;
        }
      }
      for (std::size_t bs = 0; bs < nb; ++bs) {
        const std::size_t n = n_hi - bs;
        for (std::size_t rr = 0; rr < kRows; ++rr) {
          const std::size_t y = y0 + rr;
          cd* oa = in + 3 * rr * ldi;
          cd* ob = oa + ldi;
          cd* oc = ob + ldi;
          if (y >= ny) {
            for (std::size_t x = 0; x < nx; ++x) {
              const std::size_t q = ax.position(x);
              oa[q] = ob[q] = oc[q] = 0.0;
            }
            continue;
          }
          const cd* pre = sc.rowpre.data() + rr * nx;
          const double* jr = sc.rowj.data() + rr * orders * nx;
          for (std::size_t x = 0; x < nx; ++x) {
            const std::size_t i = y * nx + x, q = ax.position(x);
            const double jp = jr[bs * nx + x], jn = jr[(bs + 1) * nx + x],
                         jm = n >= 1 ? jr[(bs + 2) * nx + x] : 0.0;
            // With the factor (-i)^n taken out (applied after the y-transform): c_n = alpha
            // J_n, the q_z part q_c c_n + r s_n with s_n = i (J_{n-1} - J_{n+1}).
            const double u = (n ? 2.0 : 1.0) * jn;
            oa[q] = mul(pre[x], cd(qc * u, r * (jm - jp)));
            ob[q] = pre[x] * (F.gx[i] * u);
            oc[q] = pre[x] * (F.gy[i] * u);
          }
        }
        ax.run(sc.x);
        cd* sums = sc.sums.data();
        tap_sums_x(ax.weights(), ax.starts(), K, 0, N, sc.x.out.data(), ax.out_stride(), sums);
        // A - q_x B and C of each row, shifted by the point's x offset, summed over the points.
        cd* xacc = sc.xacc.data() + bs * N * 2 * kRows;
        for (std::size_t k = 0; k < N; ++k) {
          const cd ph = xshift[f][g][pt * N + k];
          const cd* a = sums + k * kVx;
          cd* xa = xacc + k * 2 * kRows;
          for (std::size_t rr = 0; rr < kRows; ++rr) {
            const cd u = mul(ph, a[3 * rr] - qx[k] * a[3 * rr + 1]), v = mul(ph, a[3 * rr + 2]);
            xa[2 * rr] = pt == 0 ? u : xa[2 * rr] + u;
            xa[2 * rr + 1] = pt == 0 ? v : xa[2 * rr + 1] + v;
          }
        }
      }
    }
    for (std::size_t bs = 0; bs < nb; ++bs) {
      cd* xo = ws.xo.data() + bs * slot;
      const cd* xacc = sc.xacc.data() + bs * N * 2 * kRows;
      for (std::size_t k = 0; k < N; ++k) {
        const cd* xa = xacc + k * 2 * kRows;
        cd* o = xo + (k * ny + y0) * 2;
        for (std::size_t rr = 0; rr < kRows && y0 + rr < ny; ++rr) {
          stream(o + 2 * rr, xa[2 * rr]);
          stream(o + 2 * rr + 1, xa[2 * rr + 1]);
        }
      }
    }
    stream_fence();
  };

  const std::function<void(std::size_t)> yblock = [&](std::size_t b) {
    ThreadScratch& sc = thread_scratch();
    ay.prepare(sc.y);
    sc.sums.resize(N * std::max(kVx, batch * kVy));
    cd* in = sc.y.in.data();
    const std::size_t k0 = b * kCols, K = ay.taps();
    std::size_t lmin = N, lmax = 0;
    for (std::size_t c = 0; c < kCols; ++c) {
      const std::size_t k = k0 + c;
      if (k < N && lay.hi[k] > lay.lo[k]) {
        lmin = std::min(lmin, lay.lo[k]);
        lmax = std::max(lmax, lay.hi[k]);
      }
    }
    if (lmin >= lmax) return;
    const std::size_t span_l = lmax - lmin;
    for (std::size_t s = 0; s < nb; ++s) {
      for (std::size_t c = 0; c < kCols; ++c) {
        const std::size_t k = k0 + c;
        const bool live = k < N && lay.hi[k] > lay.lo[k];
        const cd* src = live ? ws.xo.data() + s * slot + k * ny * 2 : nullptr;
        const std::size_t* pos = ay.positions();
        cd* da = in + 2 * c * ay.in_stride();
        cd* dc = da + ay.in_stride();
        if (live)
          for (std::size_t y = 0; y < ny; ++y) {
            da[pos[y]] = src[2 * y];
            dc[pos[y]] = src[2 * y + 1];
          }
        else
          for (std::size_t y = 0; y < ny; ++y) da[pos[y]] = dc[pos[y]] = 0.0;
      }
      ay.run(sc.y);
      tap_sums_y(ay.weights(), ay.starts(), K, lmin, lmax, sc.y.out.data(), ay.out_stride(),
                 sc.sums.data() + s * span_l * kVy);
    }
    const bool last_group = gi + 1 == groups;
    const std::vector<cd>* ysh = exact ? &yshift[f][g] : nullptr;
    for (std::size_t c = 0; c < kCols; ++c) {
      const std::size_t k = k0 + c;
      if (k >= N || lay.hi[k] <= lay.lo[k]) continue;
      for (std::size_t l = lay.lo[k]; l < lay.hi[k]; ++l) {
        const std::size_t j = lay.off[k] + (l - lay.lo[k]);
        const double t = node_t(lay, k, l);
        cd b1 = first ? cd(0) : ws.state[2 * j], b2 = first ? cd(0) : ws.state[2 * j + 1];
        for (std::size_t s = 0; s < nb; ++s) {
          const std::size_t nn = n_hi - s;
          const cd* a = sc.sums.data() + (s * span_l + (l - lmin)) * kVy + 2 * c;
          cd I = a[0] - qy[l] * a[1];
          if (ysh) I = mul(I, (*ysh)[l]);
          I = rotate(I, nn);
          if (groups > 1) {
            cd& acc = ws.it[s * lay.count + j];
            if (!last_group) {
              acc = gi == 0 ? I : acc + I;
              continue;
            }
            I += acc;
          }
          if (nn > 0) {
            const cd bn = I + 2 * t * b1 - b2;
            b2 = b1;
            b1 = bn;
          } else {
            const cd v = I + t * b1 - b2;
            out[l * N + k] = std::norm(v) * norm;
            // The amplitude with the global phase exp(-i q_z h_c) put back, so that tiles of
            // different height ranges add coherently (KirchhoffScanPartial::coherent).
            if (amplitude) {
              const double mx = -1 + delta * static_cast<double>(k),
                           my = -1 + delta * static_cast<double>(l);
              const double qz = qmag * std::sqrt(std::max(0.0, 1 - mx * mx - my * my));
              (*amplitude)[l * N + k] = v * std::sqrt(norm) * std::polar(1.0, -qz * hc);
            }
          }
        }
        if (n_hi + 1 > nb && !(groups > 1 && !last_group)) {  // not the last batch
          ws.state[2 * j] = b1;
          ws.state[2 * j + 1] = b2;
        }
      }
    }
  };

  for (n_hi = terms - 1;; n_hi -= nb) {
    nb = std::min(batch, n_hi + 1);
    f = g = gi = 0;
    if (exact) {
      for (f = 0; f < fam.size(); ++f)
        for (g = 0; g < rules[f].size(); ++g, ++gi) {
          pool.run(xblocks, threads, xblock_exact);
          pool.run(yblocks, threads, yblock);
        }
    } else {
      pool.run(xblocks, threads, xblock);
      pool.run(yblocks, threads, yblock);
    }
    first = false;
    if (n_hi + 1 == nb) break;
  }
  give_workspace(std::move(wsp));
  return out;
}

}  // namespace

std::vector<double> kirchhoff_table_fast(const KirchhoffPatch& p, double lambda_q,
                                         std::size_t resolution, double accuracy,
                                         KirchhoffFastInfo* info, bool chirp_z,
                                         KirchhoffIntegration m, double band_x, double band_y,
                                         std::vector<std::complex<double>>* amplitude) {
  return table_fast(p, lambda_q, resolution, accuracy, info, chirp_z, m, band_x, band_y, amplitude);
}

}  // namespace microbrdf
