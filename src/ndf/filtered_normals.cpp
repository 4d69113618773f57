// Gaussian-weighted local plane fits at every sample (Dong 2015 section 5.1), computed with
// separable correlations of masked moment images (docs/theory.md §3.3: first-order normalized
// convolution). Coordinates inside are in units of the filter sigma for conditioning.
//
// The pass streams: the scan is cut into column blocks (a few dozen to a hundred columns, enough
// blocks for every thread); each block is walked top to bottom with a ring of its last 2h + 1
// x-filtered rows (5 moment channels), so the y filter reads contiguous rows that stay in the
// core's cache, and nothing of the size of the scan is allocated but the output. Every output
// value is summed in the same order as a plain row pass and column pass would sum it (taps in
// ascending order, zeros outside the scan), so the normals are the same bit for bit whatever the
// block width and the thread count.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <limits>
#include <memory>
#include <new>
#include <numbers>
#include <string>
#include <vector>

#include "core/aligned_array.hpp"
#include "core/helper_pool.hpp"
#include "core/length_text.hpp"
#include "core/simd_clones.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/memory_budget.hpp"
#include "microbrdf/ndf_estimate.hpp"
#include "ndf/filtered_normals_core.hpp"

namespace microbrdf {
namespace {

struct Kernel {
  long half = 0;                 // taps k in [-half, half]
  std::vector<double> g, u, u2;  // g(k), g(k) u_k, g(k) u_k^2 with u_k = k d / sigma
  double sum = 0;                // sum of g
};

// Taps |k| <= floor(truncate sigma / spacing), of which only |k| <= max_half are stored: a tap
// farther than the scan is long reads only the zero padding outside it, so dropping it changes
// no output bit, but `sum` (the support rule's reference mass) is that of the whole kernel.
Kernel make_kernel(double spacing, double sigma, double truncate, long max_half) {
  Kernel k;
  const double reach = std::floor(truncate * sigma / spacing);
  // A kernel of more than 2^20 taps each way is far longer than the scan: its sum is the
  // integral of the Gaussian over the taps' span (the Riemann sum of a Gaussian sampled finer
  // than its sigma equals the integral to double precision).
  constexpr double kSummedTaps = 1 << 20;
  const bool summed = reach <= kSummedTaps;
  const long full = summed ? static_cast<long>(reach) : max_half;
  k.half = std::min(full, max_half);
  for (long i = -full; i <= full; ++i) {
    double u = static_cast<double>(i) * spacing / sigma;
    double g = std::exp(-0.5 * u * u);
    if (summed) k.sum += g;
    if (i < -k.half || i > k.half) continue;
    k.g.push_back(g);
    k.u.push_back(g * u);
    k.u2.push_back(g * u * u);
  }
  if (!summed)
    k.sum = sigma / spacing * std::sqrt(2 * std::numbers::pi) *
            std::erf((reach + 0.5) * spacing / sigma / std::sqrt(2.0));
  return k;
}

using AlignedBuffer = detail::AlignedArray<double>;  // grow-only scratch, 64-byte aligned

// Per-thread working set of one column block, reused across blocks and scans.
struct Workspace {
  AlignedBuffer in;    // padded input row: v then v h, 2 x (w + 2 hx)
  AlignedBuffer xrow;  // one x-filtered row: 5 channels x w
  AlignedBuffer ring;  // (2 hy + 1) x-filtered rows, by column group (see kSlot)
  AlignedBuffer mom;   // 9 moment rows x w
};

Workspace& workspace() {
  static thread_local Workspace w;
  return w;
}

// x filter of one padded row: o_c[j] = sum_k in[j + k] w_c[k], k = 0..taps-1 in ascending order
// (the padded row starts half a kernel left of the block). Channels: v g, v u, v u^2, vh g, vh u.
MICROBRDF_SIMD_CLONES
void x_filter(const double* __restrict v, const double* __restrict vh, std::size_t w,
              const double* __restrict g, const double* __restrict u, const double* __restrict u2,
              std::size_t taps, double* __restrict o) {
  double* __restrict o0 = o;
  double* __restrict o1 = o + w;
  double* __restrict o2 = o + 2 * w;
  double* __restrict o3 = o + 3 * w;
  double* __restrict o4 = o + 4 * w;
  for (std::size_t j = 0; j < w; ++j) o0[j] = o1[j] = o2[j] = o3[j] = o4[j] = 0.0;
  std::size_t k = 0;
  // Four taps per sweep: ((((acc + a0 w0) + a1 w1) + a2 w2) + a3 w3) is the sequential sum.
  for (; k + 4 <= taps; k += 4) {
    const double g0 = g[k], g1 = g[k + 1], g2 = g[k + 2], g3 = g[k + 3];
    const double u0 = u[k], u1 = u[k + 1], u_2 = u[k + 2], u3 = u[k + 3];
    const double q0 = u2[k], q1 = u2[k + 1], q2 = u2[k + 2], q3 = u2[k + 3];
    const double* a = v + k;
    const double* b = vh + k;
    for (std::size_t j = 0; j < w; ++j) {
      const double a0 = a[j], a1 = a[j + 1], a2 = a[j + 2], a3 = a[j + 3];
      const double b0 = b[j], b1 = b[j + 1], b2 = b[j + 2], b3 = b[j + 3];
      o0[j] = (((o0[j] + a0 * g0) + a1 * g1) + a2 * g2) + a3 * g3;
      o1[j] = (((o1[j] + a0 * u0) + a1 * u1) + a2 * u_2) + a3 * u3;
      o2[j] = (((o2[j] + a0 * q0) + a1 * q1) + a2 * q2) + a3 * q3;
      o3[j] = (((o3[j] + b0 * g0) + b1 * g1) + b2 * g2) + b3 * g3;
      o4[j] = (((o4[j] + b0 * u0) + b1 * u1) + b2 * u_2) + b3 * u3;
    }
  }
  for (; k < taps; ++k) {
    const double g0 = g[k], u0 = u[k], q0 = u2[k];
    const double* a = v + k;
    const double* b = vh + k;
    for (std::size_t j = 0; j < w; ++j) {
      o0[j] += a[j] * g0;
      o1[j] += a[j] * u0;
      o2[j] += a[j] * q0;
      o3[j] += b[j] * g0;
      o4[j] += b[j] * u0;
    }
  }
}

// Four doubles in one vector register (GCC/Clang vector extension; two SSE2 registers in the
// baseline build, one AVX2 register in the AVX2 clone).
typedef double V4 __attribute__((vector_size(32), may_alias));

// The ring of x-filtered rows is stored column group by column group: for each group of four
// columns, its 2 hy + 1 ring slots one after the other, each slot the 5 channels x 4 columns
// (160 bytes). The y filter of one group then reads one contiguous run of memory (two at the
// ring's wrap), which stays in L1 and streams for the prefetcher.
constexpr std::size_t kSlot = 20;  // doubles per ring slot of one column group

// y filter of the column groups 0..groups-1: m[r][j] = sum over taps t (ascending) of
// x-row (first + t)[channel][j] * weight, for the nine moments m00, m01, m02 (v g with g, u,
// u^2), m10, m11 (v u with g, u), m20 (v u^2 with g), b00, b01 (v h g with g, u), b10 (v h u
// with g); the nine sums of four columns stay in registers. m has 9 rows of `stride` doubles.
MICROBRDF_SIMD_CLONES
void y_filter(const double* __restrict ring, std::size_t ring_rows, std::size_t first,
              std::size_t ntaps, std::size_t groups, const double* __restrict g,
              const double* __restrict u, const double* __restrict u2, double* __restrict m,
              std::size_t stride) {
  for (std::size_t jv = 0; jv < groups; ++jv) {
    const double* base = ring + jv * ring_rows * kSlot;
    const V4 zero = {0, 0, 0, 0};
    V4 m00 = zero, m01 = zero, m02 = zero, m10 = zero, m11 = zero, m20 = zero, b00 = zero,
       b01 = zero, b10 = zero;
    std::size_t slot = first;
    for (std::size_t t = 0; t < ntaps; ++t) {
      const double* r = base + slot * kSlot;
      slot = slot + 1 == ring_rows ? 0 : slot + 1;
      const V4 c0 = *reinterpret_cast<const V4*>(r);
      const V4 c1 = *reinterpret_cast<const V4*>(r + 4);
      const V4 c2 = *reinterpret_cast<const V4*>(r + 8);
      const V4 c3 = *reinterpret_cast<const V4*>(r + 12);
      const V4 c4 = *reinterpret_cast<const V4*>(r + 16);
      const V4 gg = {g[t], g[t], g[t], g[t]}, uu = {u[t], u[t], u[t], u[t]},
               qq = {u2[t], u2[t], u2[t], u2[t]};
      m00 += c0 * gg;
      m01 += c0 * uu;
      m02 += c0 * qq;
      m10 += c1 * gg;
      m11 += c1 * uu;
      m20 += c2 * gg;
      b00 += c3 * gg;
      b01 += c3 * uu;
      b10 += c4 * gg;
    }
    const std::size_t j = 4 * jv;
    *reinterpret_cast<V4*>(m + j) = m00;
    *reinterpret_cast<V4*>(m + stride + j) = m01;
    *reinterpret_cast<V4*>(m + 2 * stride + j) = m02;
    *reinterpret_cast<V4*>(m + 3 * stride + j) = m10;
    *reinterpret_cast<V4*>(m + 4 * stride + j) = m11;
    *reinterpret_cast<V4*>(m + 5 * stride + j) = m20;
    *reinterpret_cast<V4*>(m + 6 * stride + j) = b00;
    *reinterpret_cast<V4*>(m + 7 * stride + j) = b01;
    *reinterpret_cast<V4*>(m + 8 * stride + j) = b10;
  }
}

// Solves the 3x3 normal equations of the plane fit (moments in sigma units); returns false if
// the support is too thin or the system is ill-conditioned.
bool solve_plane(double m00, double m10, double m01, double m20, double m11, double m02, double b00,
                 double b10, double b01, double min_mass, double& bx, double& by) {
  if (!(m00 >= min_mass)) return false;
  // Reduce to the 2x2 system for the slopes: covariance of (u, v) and of (u, v) with h.
  const double cu = m10 / m00, cv = m01 / m00;
  const double suu = m20 - m10 * cu, svv = m02 - m01 * cv, suv = m11 - m10 * cv;
  const double shu = b10 - b00 * cu, shv = b01 - b00 * cv;
  const double det = suu * svv - suv * suv;
  if (!(det > 1e-10 * m00 * m00)) return false;
  bx = (shu * svv - shv * suv) / det;
  by = (shv * suu - shu * suv) / det;
  return true;
}

void set_normal(double bx_phys, double by_phys, double* m) {
  const double inv = 1.0 / std::sqrt(1.0 + bx_phys * bx_phys + by_phys * by_phys);
  m[0] = -bx_phys * inv;
  m[1] = -by_phys * inv;
  m[2] = inv;
}

// The plane fits of one row of moments (the arithmetic of solve_plane and set_normal without
// branches, so that it vectorises: IEEE division and square root round the same in vector
// registers; this file is built with -fno-math-errno, so sqrt of 1 + bx^2 + by^2 needs no library
// call). ok[j] = 1 where the fit is accepted.
MICROBRDF_SIMD_CLONES
void solve_row(const double* __restrict m, std::size_t stride, std::size_t n, double min_mass,
               double sigma, double* __restrict ox, double* __restrict oy, double* __restrict oz,
               double* __restrict ok) {
  const double* __restrict pm00 = m;
  const double* __restrict pm01 = m + stride;
  const double* __restrict pm02 = m + 2 * stride;
  const double* __restrict pm10 = m + 3 * stride;
  const double* __restrict pm11 = m + 4 * stride;
  const double* __restrict pm20 = m + 5 * stride;
  const double* __restrict pb00 = m + 6 * stride;
  const double* __restrict pb01 = m + 7 * stride;
  const double* __restrict pb10 = m + 8 * stride;
  for (std::size_t j = 0; j < n; ++j) {
    const double m00 = pm00[j], m01 = pm01[j], m02 = pm02[j], m10 = pm10[j], m11 = pm11[j],
                 m20 = pm20[j], b00 = pb00[j], b01 = pb01[j], b10 = pb10[j];
    const double cu = m10 / m00, cv = m01 / m00;
    const double suu = m20 - m10 * cu, svv = m02 - m01 * cv, suv = m11 - m10 * cv;
    const double shu = b10 - b00 * cu, shv = b01 - b00 * cv;
    const double det = suu * svv - suv * suv;
    const double bx = (shu * svv - shv * suv) / det / sigma;
    const double by = (shv * suu - shu * suv) / det / sigma;
    const double inv = 1.0 / std::sqrt(1.0 + bx * bx + by * by);
    ox[j] = -bx * inv;
    oy[j] = -by * inv;
    oz[j] = inv;
    ok[j] = ((m00 >= min_mass) & (det > 1e-10 * m00 * m00)) ? 1.0 : 0.0;
  }
}

// Beyond 38.6 sigma the Gaussian weight exp(-u^2/2) is 0 in double precision: a wider
// truncation only adds zero taps.
constexpr double kMaxTruncate = 40;

// The scan's longest side in metres (the largest distance a kernel tap can usefully reach).
double longest_side(const Surface& s) {
  return std::max(static_cast<double>(s.nx) * s.dx, static_cast<double>(s.ny) * s.dy);
}

// The error about the data of `s`: naming its file when it has one.
[[noreturn]] void data_error(const Surface& s, const std::string& problem) {
  if (s.meta.source_path.empty()) throw InputError(problem);
  throw FileError(s.meta.source_path, problem);
}

void check_args(const Surface& s, double sigma, double truncate) {
  if (!(sigma > 0) || !std::isfinite(sigma)) throw InputError("filter sigma must be positive");
  if (!(truncate >= 1 && truncate <= kMaxTruncate))
    throw InputError("kernel truncation must lie in 1..40 sigma");
  if (s.size() == 0) throw InputError("empty surface");
  if (!(s.dx > 0 && s.dy > 0 && std::isfinite(s.dx) && std::isfinite(s.dy)))
    data_error(s, "sample spacing must be positive and finite");
  // A sigma longer than the scan makes every window the whole scan (one plane, one normal): the
  // NDF says nothing, and the kernel's taps (truncate sigma / spacing each way) only cost time
  // and memory. This bound also keeps the tap count finite whatever the spacing.
  const double side = longest_side(s);
  if (!(sigma <= side))
    data_error(s, "filter sigma " + detail::format_length_any(sigma) +
                      " is longer than the scan (" + std::to_string(s.nx) + " x " +
                      std::to_string(s.ny) + " samples of " + detail::format_length_any(s.dx) +
                      " x " + detail::format_length_any(s.dy) + ", longest side " +
                      detail::format_length_any(side) +
                      "): every plane fit would span the whole scan; use a filter sigma of at "
                      "most the scan's side (a few sample spacings to a few microns is usual), "
                      "or check --spacing");
}

// The working memory of one pass (per-thread column-block buffers and the kernels), checked
// against the memory budget before anything is allocated.
void check_pass_memory(const Surface& s, std::size_t hx, std::size_t hy, std::size_t threads) {
  const std::uint64_t w4 = 128, padded = w4 + 2 * hx;
  const std::uint64_t per_thread = 2 * padded + 5 * w4 + (2 * hy + 1) * 5 * w4 + 13 * w4;
  const std::uint64_t doubles = mul_sat(per_thread, threads) + 3 * (2 * hx + 1) + 3 * (2 * hy + 1);
  check_memory(s.meta.source_path.empty() ? std::string("filtered normals") : s.meta.source_path,
               mul_sat(doubles, sizeof(double)),
               "the filtered normals' working buffers (kernel of " + std::to_string(2 * hy + 1) +
                   " rows x " + std::to_string(threads) + " threads)");
}

}  // namespace

namespace detail {

double* thread_scratch(std::size_t n, int slot) {
  static thread_local AlignedBuffer buf[3];
  return buf[std::clamp(slot, 0, 2)].get(n);
}

void filtered_normals_into(const Surface& s, double sigma, double truncate, double min_support,
                           double* out_mx, double* out_my, double* out_mz, std::size_t& used,
                           std::size_t& skipped) {
  check_args(s, sigma, truncate);
  const std::size_t nx = s.nx, ny = s.ny;
  const Kernel kx = make_kernel(s.dx, sigma, truncate, static_cast<long>(nx) - 1),
               ky = make_kernel(s.dy, sigma, truncate, static_cast<long>(ny) - 1);
  const double mean = s.valid_mean();
  const double min_mass = min_support * kx.sum * ky.sum;
  const auto hx = static_cast<std::size_t>(kx.half), hy = static_cast<std::size_t>(ky.half);
  const std::size_t taps_x = 2 * hx + 1, ring_rows = 2 * hy + 1;
  const double nan = std::numeric_limits<double>::quiet_NaN();

  // Column blocks: at most 128 columns, and at least sixteen per thread, taken one at a time: a
  // thread the scheduler holds back delays the end by one small block at most; widths multiple
  // of 8.
  const int threads = omp_get_max_threads();
  check_pass_memory(s, hx, hy, static_cast<std::size_t>(threads));
  std::size_t blocks =
      std::max<std::size_t>((nx + 127) / 128, 16 * static_cast<std::size_t>(threads));
  std::size_t width = (nx + blocks - 1) / blocks;
  width = std::max<std::size_t>(8, (width + 7) / 8 * 8);
  blocks = (nx + width - 1) / width;

  std::atomic<std::size_t> n_used{0}, n_skipped{0};
  auto block = [&](std::size_t bi) {
    const std::size_t x0 = bi * width;
    const std::size_t w = std::min(width, nx - x0);
    const std::size_t w4 = (w + 3) / 4 * 4;  // ring rows padded to whole vectors
    const std::size_t padded = w4 + 2 * hx;
    Workspace& ws = workspace();
    double* in = ws.in.get(2 * padded);
    double* pv = in;
    double* ph = in + padded;
    const std::size_t groups = w4 / 4;
    double* xrow = ws.xrow.get(5 * w4);
    double* ring = ws.ring.get(ring_rows * 5 * w4);
    double* mom = ws.mom.get(13 * w4);
    double* fit = mom + 9 * w4;  // normals and acceptance of one row
    std::size_t used_b = 0, skipped_b = 0;
    for (std::size_t yin = 0; yin < ny + hy; ++yin) {
      if (yin < ny) {
        // Padded row: columns x0 - hx .. x0 + w4 + hx - 1, zero outside the scan and at holes.
        const long xa = static_cast<long>(x0) - static_cast<long>(hx);
        const std::size_t j0 = xa < 0 ? static_cast<std::size_t>(-xa) : 0;
        const std::size_t j1 =
            std::min(padded, static_cast<std::size_t>(static_cast<long>(nx) - xa));
        for (std::size_t j = 0; j < j0; ++j) pv[j] = ph[j] = 0.0;
        const std::uint8_t* vr =
            s.valid.data() + yin * nx + static_cast<std::size_t>(xa + static_cast<long>(j0)) - j0;
        const double* zr =
            s.z.data() + yin * nx + static_cast<std::size_t>(xa + static_cast<long>(j0)) - j0;
        for (std::size_t j = j0; j < j1; ++j) {
          const bool ok = vr[j] != 0;
          pv[j] = ok ? 1.0 : 0.0;
          ph[j] = ok ? zr[j] - mean : 0.0;
        }
        for (std::size_t j = j1; j < padded; ++j) pv[j] = ph[j] = 0.0;
        x_filter(pv, ph, w4, kx.g.data(), kx.u.data(), kx.u2.data(), taps_x, xrow);
        double* slot = ring + (yin % ring_rows) * kSlot;
        for (std::size_t jv = 0; jv < groups; ++jv, slot += ring_rows * kSlot)
          for (std::size_t c = 0; c < 5; ++c)
            for (std::size_t l = 0; l < 4; ++l) slot[4 * c + l] = xrow[c * w4 + 4 * jv + l];
      }
      if (yin < hy) continue;
      const std::size_t yo = yin - hy;
      // Taps inside the scan only, ascending (what a column pass with zero padding would add).
      const std::size_t t0 = yo >= hy ? 0 : hy - yo;
      const std::size_t t1 = std::min(2 * hy, hy + (ny - 1 - yo));
      y_filter(ring, ring_rows, (yo + t0 - hy) % ring_rows, t1 - t0 + 1, groups, ky.g.data() + t0,
               ky.u.data() + t0, ky.u2.data() + t0, mom, w4);
      solve_row(mom, w4, w4, min_mass, sigma, fit, fit + w4, fit + 2 * w4, fit + 3 * w4);
      const std::size_t row = yo * nx + x0;
      for (std::size_t j = 0; j < w; ++j) {
        const std::size_t i = row + j;
        double m[3] = {0, 0, 0};
        bool ok = false;
        if (s.valid[i]) {
          ok = fit[3 * w4 + j] != 0;
          if (ok) {
            m[0] = fit[j];
            m[1] = fit[w4 + j];
            m[2] = fit[2 * w4 + j];
            ++used_b;
          } else {
            ++skipped_b;
          }
        }
        if (out_mz) {
          out_mx[i] = m[0];
          out_my[i] = m[1];
          out_mz[i] = m[2];
        } else {
          out_mx[i] = ok ? m[0] : nan;
          out_my[i] = m[1];
        }
      }
    }
    n_used += used_b;
    n_skipped += skipped_b;
  };
  detail::HelperPool::instance().run(blocks, threads, block);
  used = n_used;
  skipped = n_skipped;
}

namespace {

// Below this many points one thread splats (a fork and join costs more than it saves).
constexpr std::size_t kParallelSplatPoints = std::size_t{1} << 16;
constexpr std::size_t kSplatBlock = std::size_t{1} << 14;  // points per helper-pool item
constexpr std::uint32_t kNoCell = 0xFFFFFFFFu;

}  // namespace

void splat_normals(double* mx, double* my, std::size_t n, double weight, TabulatedNdf& t,
                   int threads) {
  const std::size_t res = t.resolution();
  double* d = t.values().data();
  const double inv = 1.0 / t.spacing();
  const double last = static_cast<double>(res - 1);
  const double ox = t.window().x0(), oy = t.window().y0();  // the first node (-1 unless zoomed)
  // Pass 1, blocks of points on the helper threads: each point's table cell (row-major index,
  // kNoCell outside the table's square or for NaN) and its bilinear weights, the weights written
  // over mx and my.
  std::uint32_t* cell = reinterpret_cast<std::uint32_t*>(thread_scratch((n + 1) / 2, 2));
  const std::function<void(std::size_t)> locate = [&](std::size_t b) {
    const std::size_t end = std::min(n, (b + 1) * kSplatBlock);
    for (std::size_t i = b * kSplatBlock; i < end; ++i) {
      const double fx = (mx[i] - ox) * inv, fy = (my[i] - oy) * inv;  // NaN fails the test
      if (!(fx >= 0 && fx <= last && fy >= 0 && fy <= last)) {
        cell[i] = kNoCell;
        continue;
      }
      const auto ix = static_cast<std::size_t>(std::min(std::floor(fx), last - 1));
      const auto iy = static_cast<std::size_t>(std::min(std::floor(fy), last - 1));
      cell[i] = static_cast<std::uint32_t>(iy * res + ix);
      mx[i] = fx - static_cast<double>(ix);
      my[i] = fy - static_cast<double>(iy);
    }
  };
  const int used_threads = n < kParallelSplatPoints ? 1 : threads;
  HelperPool::instance().run((n + kSplatBlock - 1) / kSplatBlock, used_threads, locate);
  // Pass 2: table rows [lo, hi) owned by one thread. Every node still receives its splats in
  // point order from exactly one thread, so the table is the same bit for bit as one splat per
  // point in a plain loop, whatever the thread count.
  auto splat_rows = [&](std::size_t lo, std::size_t hi) {
    const std::size_t first = lo * res, end = hi * res;  // cells whose rows touch [lo, hi)
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t c = cell[i];
      if (c == kNoCell || c + res < first || c >= end) continue;
      const double tx = mx[i], ty = my[i];
      double* r0 = d + c;
      if (c >= first) {
        r0[0] += weight * (1 - tx) * (1 - ty);
        r0[1] += weight * tx * (1 - ty);
      }
      if (c + res < end) {
        double* r1 = r0 + res;
        r1[0] += weight * (1 - tx) * ty;
        r1[1] += weight * tx * ty;
      }
    }
  };
  if (used_threads <= 1) {
    splat_rows(0, res);
    return;
  }
  // Bands of table rows holding equal numbers of splats (the lobe is narrow: equal row counts
  // would leave most threads idle).
  std::vector<std::size_t> per_row(res, 0);
  std::size_t total = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (cell[i] != kNoCell) ++per_row[cell[i] / res], ++total;
  const auto bands = static_cast<std::size_t>(threads);
  std::vector<std::size_t> edge{0};
  std::size_t seen = 0;
  for (std::size_t r = 0; r < res && edge.size() < bands; ++r) {
    seen += per_row[r];
    if (seen * bands >= total * edge.size()) edge.push_back(r + 1);
  }
  edge.push_back(res);
  const std::function<void(std::size_t)> band = [&](std::size_t k) {
    splat_rows(edge[k], edge[k + 1]);
  };
  HelperPool::instance().run(edge.size() - 1, threads, band);
}

}  // namespace detail

NormalField filtered_normals(const Surface& s, double sigma, double truncate, double min_support) {
  check_args(s, sigma, truncate);
  NormalField f;
  f.nx = s.nx;
  f.ny = s.ny;
  f.mx.resize(s.size());
  f.my.resize(s.size());
  f.mz.resize(s.size());
  detail::filtered_normals_into(s, sigma, truncate, min_support, f.mx.data(), f.my.data(),
                                f.mz.data(), f.used, f.skipped);
  return f;
}

bool filtered_normal_direct(const Surface& s, std::size_t ix, std::size_t iy, double sigma,
                            double truncate, double min_support, double out[3]) {
  check_args(s, sigma, truncate);
  if (!s.valid[iy * s.nx + ix]) return false;
  const Kernel kx = make_kernel(s.dx, sigma, truncate, static_cast<long>(s.nx) - 1),
               ky = make_kernel(s.dy, sigma, truncate, static_cast<long>(s.ny) - 1);
  // Heights relative to the centre sample (slopes do not depend on the offset; it only keeps
  // the sums well conditioned) so the reference costs just its window.
  const double mean = s.z[iy * s.nx + ix];
  double m00 = 0, m10 = 0, m01 = 0, m20 = 0, m11 = 0, m02 = 0, b00 = 0, b10 = 0, b01 = 0;
  for (long l = -ky.half; l <= ky.half; ++l) {
    long y = static_cast<long>(iy) + l;
    if (y < 0 || y >= static_cast<long>(s.ny)) continue;
    double vv = static_cast<double>(l) * s.dy / sigma;
    double gy = std::exp(-0.5 * vv * vv);
    for (long k = -kx.half; k <= kx.half; ++k) {
      long x = static_cast<long>(ix) + k;
      if (x < 0 || x >= static_cast<long>(s.nx)) continue;
      std::size_t j = static_cast<std::size_t>(y) * s.nx + static_cast<std::size_t>(x);
      if (!s.valid[j]) continue;
      double uu = static_cast<double>(k) * s.dx / sigma;
      double w = std::exp(-0.5 * uu * uu) * gy;
      double h = s.z[j] - mean;
      m00 += w;
      m10 += w * uu;
      m01 += w * vv;
      m20 += w * uu * uu;
      m11 += w * uu * vv;
      m02 += w * vv * vv;
      b00 += w * h;
      b10 += w * h * uu;
      b01 += w * h * vv;
    }
  }
  double bx, by;
  if (!solve_plane(m00, m10, m01, m20, m11, m02, b00, b10, b01, min_support * kx.sum * ky.sum, bx,
                   by))
    return false;
  set_normal(bx / sigma, by / sigma, out);
  return true;
}

}  // namespace microbrdf
