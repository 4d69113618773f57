// Instrument signature: convolution of a tabulated NDF with an angular Gaussian on the sphere
// (Dong 2015 section 7 uses a 1.5 deg FWHM).
//
// Mass conserving: node j carries mass D_j Delta^2 (its share of integral D(m)(m.n) dw) and
// spreads it over nodes i with weights  k_ij * Omega_i / W_j,  k_ij = exp(-theta_ij^2/(2 s^2))
// for theta_ij <= 4 s (0 beyond), Omega_i = Delta^2 / m_z,i (solid angle of node i) and
// W_j = sum_i k_ij Omega_i. Then D_i = mass_i / Delta^2 = (1/m_z,i) sum_j k_ij D_j / W'_j with
// W'_j = W_j / Delta^2 = sum_i k_ij / m_z,i. k is symmetric, so both sums are the same gather
// "out_p = sum_q k_pq v_q" over a box of nodes around p: first with v = 1/m_z (giving W'),
// then with v = D / W'. Disk distances never exceed angles, so a disk-coordinate circle of
// radius 4 s (in node units R = 4 s / Delta) holds every neighbour.
//
// theta^2 from the chord c^2 = |m_i - m_j|^2: theta = 2 asin(c/2), theta^2 = c^2 + c^4/12 +
// c^6/90 + c^8/560 + ... (truncation error < 1e-8 relative for 4 s <= 0.35 rad; wider kernels
// use asin). exp(-x) for x in [0, 8] by a degree-10 Taylor polynomial of exp(-x/16), squared
// four times (relative error < 1e-9), so that the inner loop vectorises.
//
// Cost: two gathers of ~ (pi/4) N^2 * pi R^2 kernel evaluations; N = 1025, FWHM 1.5 deg:
// R = 22.8 nodes, ~1.4e9 evaluations per gather. Rows and columns farther than R from any
// non-zero node are skipped, so narrow NDFs cost far less.
#include "microbrdf/ndf_convolve.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "microbrdf/error.hpp"

// The vector helpers below have internal linkage and are inlined: the ABI note GCC gives for
// passing 32-byte vectors without AVX does not concern them.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

namespace microbrdf {
namespace {

struct KernelParams {
  double cut2;    // (4 sigma)^2, rad^2
  double inv2s2;  // 1 / (2 sigma^2)
};

// exp(-x) for 0 <= x <= 8 (T = double or a GCC vector of doubles).
template <class T>
inline T exp_neg_small(T x) {
  const T y = x * (-1.0 / 16);
  T p = y * (1.0 / 3628800) + 1.0 / 362880;
  p = p * y + 1.0 / 40320;
  p = p * y + 1.0 / 5040;
  p = p * y + 1.0 / 720;
  p = p * y + 1.0 / 120;
  p = p * y + 1.0 / 24;
  p = p * y + 1.0 / 6;
  p = p * y + 0.5;
  p = p * y + 1.0;
  p = p * y + 1.0;
  p *= p;
  p *= p;
  p *= p;
  p *= p;
  return p;
}

// theta^2 from the squared chord s (series above).
template <class T>
inline T theta2_of_chord2(T s) {
  return s * (s * (s * (s * (1.0 / 560) + 1.0 / 90) + 1.0 / 12) + 1.0);
}

// sum over a run of neighbours q of k(p, q) v_q. dx2[k]: squared disk x-distance of the k-th
// neighbour, zq / vq its z and value, dy2 the squared y-distance of the row, zp p's z.
// Four lanes at a time with GCC/Clang vector types; compiled twice (AVX2 and baseline) and
// picked at run time. Lanes and the scalar tail compute bit-identical weights.
typedef double V4 __attribute__((vector_size(32)));

inline V4 load4(const double* p) {
  V4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

#define MICROBRDF_ROW_SUM_SERIES_BODY                                   \
  const V4 zero = {0, 0, 0, 0}, eight = {8, 8, 8, 8};                   \
  const V4 cut2 = zero + kp.cut2;                                       \
  V4 acc4 = zero;                                                       \
  std::size_t k = 0;                                                    \
  for (; k + 4 <= len; k += 4) {                                        \
    const V4 dz = load4(zq + k) - zp;                                   \
    const V4 t2 = theta2_of_chord2(load4(dx2 + k) + dy2 + dz * dz);     \
    const V4 a = t2 * kp.inv2s2;                                        \
    const V4 w = exp_neg_small<V4>(a < eight ? a : eight);              \
    acc4 += w * (t2 <= cut2 ? load4(vq + k) : zero);                    \
  }                                                                     \
  double acc = (acc4[0] + acc4[1]) + (acc4[2] + acc4[3]);               \
  for (; k < len; ++k) {                                                \
    const double dz = zq[k] - zp;                                       \
    const double t2 = theta2_of_chord2(dx2[k] + dy2 + dz * dz);         \
    const double a = t2 * kp.inv2s2;                                    \
    if (t2 <= kp.cut2) acc += exp_neg_small(a < 8.0 ? a : 8.0) * vq[k]; \
  }                                                                     \
  return acc;

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define MICROBRDF_HAVE_V3 1
__attribute__((target("arch=x86-64-v3"))) double row_sum_series_v3(const double* dx2,
                                                                   const double* zq,
                                                                   const double* vq,
                                                                   std::size_t len, double dy2,
                                                                   double zp, KernelParams kp) {
  MICROBRDF_ROW_SUM_SERIES_BODY
}
#endif

double row_sum_series(const double* dx2, const double* zq, const double* vq, std::size_t len,
                      double dy2, double zp, KernelParams kp) {
  MICROBRDF_ROW_SUM_SERIES_BODY
}

double row_sum_exact(const double* dx2, const double* zq, const double* vq, std::size_t len,
                     double dy2, double zp, KernelParams kp) {
  double acc = 0;
  for (std::size_t k = 0; k < len; ++k) {
    const double dz = zq[k] - zp;
    const double c = std::sqrt(dx2[k] + dy2 + dz * dz);
    const double th = 2 * std::asin(std::min(1.0, 0.5 * c));
    if (th * th <= kp.cut2) acc += std::exp(-th * th * kp.inv2s2) * vq[k];
  }
  return acc;
}

struct Grid {
  std::size_t n = 0;
  double h = 0;
  std::vector<double> z;     // m_z of the node, 0 on/outside the unit circle
  std::vector<char> inside;  // node strictly inside the unit circle
};

// out[p] = sum_{q in disk circle of radius R around p} k(p, q) v[q] for every p with
// want[p]; others 0. Uses the extent of the non-zero entries of v to skip empty work.
void gather(const Grid& g, const std::vector<double>& v, const std::vector<char>& want,
            double r_nodes, KernelParams kp, bool series, std::vector<double>& out) {
  const std::size_t n = g.n;
  const auto r = static_cast<std::ptrdiff_t>(std::min(std::floor(r_nodes), double(n - 1)));
  const auto nn = static_cast<std::ptrdiff_t>(n);
  // Squared x-distances by offset -r..r, and each row offset's half-width in x.
  std::vector<double> dx2(static_cast<std::size_t>(2 * r + 1));
  std::vector<std::ptrdiff_t> half(static_cast<std::size_t>(2 * r + 1));
  for (std::ptrdiff_t k = -r; k <= r; ++k) {
    dx2[static_cast<std::size_t>(k + r)] = double(k) * double(k) * g.h * g.h;
    half[static_cast<std::size_t>(k + r)] = static_cast<std::ptrdiff_t>(
        std::floor(std::sqrt(std::max(0.0, r_nodes * r_nodes - double(k * k)))));
  }
  // Non-zero extent of v per row.
  std::vector<std::ptrdiff_t> lo(n, nn), hi(n, -1);
  for (std::size_t iy = 0; iy < n; ++iy)
    for (std::size_t ix = 0; ix < n; ++ix)
      if (v[iy * n + ix] != 0) {
        lo[iy] = std::min(lo[iy], std::ptrdiff_t(ix));
        hi[iy] = std::max(hi[iy], std::ptrdiff_t(ix));
      }
  out.assign(n * n, 0.0);
  auto row_sum = series ? row_sum_series : row_sum_exact;
#ifdef MICROBRDF_HAVE_V3
  if (series && __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"))
    row_sum = row_sum_series_v3;
#endif
#pragma omp parallel for schedule(dynamic, 4)
  for (std::ptrdiff_t py = 0; py < nn; ++py) {
    for (std::ptrdiff_t px = 0; px < nn; ++px) {
      const std::size_t p = std::size_t(py) * n + std::size_t(px);
      if (!want[p]) continue;
      const double zp = g.z[p];
      double acc = 0;
      for (std::ptrdiff_t oy = -r; oy <= r; ++oy) {
        const std::ptrdiff_t qy = py + oy;
        if (qy < 0 || qy >= nn || hi[std::size_t(qy)] < 0) continue;
        const std::ptrdiff_t hw = half[std::size_t(oy + r)];
        const std::ptrdiff_t a = std::max({px - hw, lo[std::size_t(qy)], std::ptrdiff_t(0)});
        const std::ptrdiff_t b = std::min({px + hw, hi[std::size_t(qy)], nn - 1});
        if (b < a) continue;
        const std::size_t q0 = std::size_t(qy) * n + std::size_t(a);
        acc += row_sum(&dx2[std::size_t(a - px + r)], &g.z[q0], &v[q0], std::size_t(b - a + 1),
                       dx2[std::size_t(oy + r)], zp, kp);
      }
      out[p] = acc;
    }
  }
}

}  // namespace

TabulatedNdf convolve_angular_gaussian(const TabulatedNdf& ndf, double fwhm_rad) {
  if (!(fwhm_rad > 0)) return ndf;
  const std::size_t n = ndf.resolution();
  const double sigma = fwhm_rad / (2 * std::sqrt(2 * std::numbers::ln2));
  const double cut = 4 * sigma;
  const KernelParams kp{cut * cut, 1 / (2 * sigma * sigma)};
  const bool series = cut <= 0.35;

  Grid g;
  g.n = n;
  g.h = ndf.spacing();
  g.z.assign(n * n, 0.0);
  g.inside.assign(n * n, 0);
  std::vector<double> inv_z(n * n, 0.0);
  std::vector<char> source(n * n, 0);
  for (std::size_t iy = 0; iy < n; ++iy)
    for (std::size_t ix = 0; ix < n; ++ix) {
      const double x = ndf.node_x(ix), y = ndf.node_y(iy), r2 = x * x + y * y;
      if (r2 >= 1) continue;
      const std::size_t p = iy * n + ix;
      g.z[p] = std::sqrt(1 - r2);
      g.inside[p] = 1;
      inv_z[p] = 1 / g.z[p];
      source[p] = ndf.at(ix, iy) != 0;
    }

  // Disk circle radius in nodes; the chord never exceeds the angle, and the disk distance
  // never exceeds the chord.
  const double r_nodes = std::min(cut, 2.0) / g.h;
  // Each node gathers from a square of (2 r + 1)^2 nodes, twice: the work grows as FWHM^2 N^4,
  // and a term costs about ten times more past the series' reach (an exp each). On 1025^2 nodes
  // 10 deg (series, 1.5e11 terms) takes about 7 s and 17 deg (4.4e11 exp terms) two minutes. An
  // instrument resolves a few degrees: past 2e11 series-term equivalents (about 10 s; 11.5 deg
  // at 1025 nodes, 60 deg at 257) the width is not an instrument's, and the run would look hung.
  constexpr double kMaxKernelWork = 2e11;
  const double side = 2 * std::floor(r_nodes) + 1;
  const double terms = 2 * side * side * std::numbers::pi / 4 * double(n) * double(n);
  if (!(terms * (series ? 1 : 10) <= kMaxKernelWork)) {
    char why[240];
    std::snprintf(why, sizeof why,
                  "--instrument-fwhm %.4g deg on a %zu x %zu table needs %.2g kernel terms (a "
                  "bound of %.0g): an instrument resolves a few degrees; give a smaller FWHM or "
                  "resolution",
                  fwhm_rad * 180 / std::numbers::pi, n, n, terms * (series ? 1 : 10),
                  kMaxKernelWork);
    throw InputError(why);
  }

  // W'_j = sum_i k_ij / m_z,i for the source nodes.
  std::vector<double> w;
  gather(g, inv_z, source, r_nodes, kp, series, w);
  std::vector<double> q(n * n, 0.0);
  for (std::size_t p = 0; p < n * n; ++p)
    if (source[p]) q[p] = ndf.values()[p] / w[p];
  std::vector<double> sum;
  gather(g, q, g.inside, r_nodes, kp, series, sum);

  TabulatedNdf out(n, ndf.window());
  out.meta = ndf.meta;
  for (std::size_t p = 0; p < n * n; ++p) out.values()[p] = g.inside[p] ? sum[p] * inv_z[p] : 0.0;
  char note[96];
  std::snprintf(note, sizeof note, "convolved with an angular Gaussian, FWHM %.6g deg",
                fwhm_rad * 180 / std::numbers::pi);
  out.meta.notes = out.meta.notes.empty() ? std::string(note) : out.meta.notes + "; " + note;
  return out;
}

// Convolution with a measured signature S (a small lobe about the pole): each predicted node's
// mass is moved along S's slope offsets, i.e. P * S on the disk in slope-offset approximation
// (the signatures are ~1 deg wide, where disk offsets and angles agree to < 1e-4 relative).
TabulatedNdf convolve_signature(const TabulatedNdf& p, const TabulatedNdf& s) {
  // The signature on nodes of the prediction's spacing, centred on the pole (node n/2).
  const TabulatedNdf sig = s.resampled(p.resolution(), zoom_window(0, 0, p.window().half));
  const std::size_t n = p.resolution();
  const long c = static_cast<long>(n / 2);
  std::vector<std::pair<long, long>> off;
  std::vector<double> w;
  double wsum = 0;
  for (std::size_t iy = 0; iy < n; ++iy)
    for (std::size_t ix = 0; ix < n; ++ix) {
      const double v = sig.at(ix, iy);
      if (v > 1e-6 * sig.at(std::size_t(c), std::size_t(c)) && std::isfinite(v)) {
        off.push_back({long(ix) - c, long(iy) - c});
        w.push_back(v);
        wsum += v;
      }
    }
  if (!(wsum > 0)) throw InputError("the instrument signature has no mass");
  TabulatedNdf out(n, p.window());
  for (std::size_t iy = 0; iy < n; ++iy)
    for (std::size_t ix = 0; ix < n; ++ix) {
      const double v = p.at(ix, iy);
      if (!(v > 0)) continue;
      for (std::size_t k = 0; k < off.size(); ++k) {
        const long x = long(ix) + off[k].first, y = long(iy) + off[k].second;
        if (x < 0 || y < 0 || x >= long(n) || y >= long(n)) continue;
        out.at(std::size_t(x), std::size_t(y)) += v * w[k] / wsum;
      }
    }
  out.clear_outside_disk();
  out.meta = p.meta;
  const std::string note =
      "convolved with a measured instrument signature" +
      (s.meta.sources.empty() ? std::string() : " (" + s.meta.sources[0] + ")");
  out.meta.notes = out.meta.notes.empty() ? note : out.meta.notes + "; " + note;
  return out;
}

TabulatedNdf apply_instrument(const TabulatedNdf& ndf, double fwhm_rad,
                              const TabulatedNdf* signature) {
  if (!(fwhm_rad >= 0) || !std::isfinite(fwhm_rad))
    throw InputError("--instrument-fwhm must be a finite angle >= 0");
  if (fwhm_rad > 0 && signature)
    throw InputError("give --instrument-fwhm or --instrument, not both");
  if (signature) return convolve_signature(ndf, *signature);
  return convolve_angular_gaussian(ndf, fwhm_rad);
}

}  // namespace microbrdf
