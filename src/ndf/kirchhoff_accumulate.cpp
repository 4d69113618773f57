// Kirchhoff distribution of scans and scan sets: tiling into coherence-area patches and
// intensity averaging (Dong 2015 App. A; docs/theory.md §4.5).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "microbrdf/error.hpp"
#include "microbrdf/kirchhoff.hpp"

namespace microbrdf {
namespace {

// round(n dx / patch) equal tiles (at least 1); the remainder of n / tiles is left out.
void tiling(std::size_t n, double d, double patch, std::size_t& count, std::size_t& len) {
  count = 1;
  if (patch > 0) {
    // Clamped in double before the conversion: a patch of 1e-300 m asks for 1e295 tiles, which
    // no integer holds (the conversion would be undefined and gave 0 tiles, a division by 0).
    const double c = std::round(static_cast<double>(n) * d / patch);
    count = c >= 1 ? static_cast<std::size_t>(std::min(c, static_cast<double>(n))) : 1;
  }
  count = std::clamp<std::size_t>(count, 1, std::max<std::size_t>(n, 1));
  len = n / count;
}

}  // namespace

std::size_t kirchhoff_auto_supersample(std::size_t resolution, double lambda_q, double lx,
                                       double ly) {
  const double delta = 2.0 / static_cast<double>(resolution - 1);
  const double need = delta * 2 * std::max(lx, ly) / lambda_q;  // S >= need
  auto s = static_cast<std::size_t>(std::ceil(std::min(need, 1e6) - 1e-9));
  s = std::max<std::size_t>(s, 1);
  if (s % 2 == 0) ++s;
  // Never more than a 1025^2 sub-node table (the default table's cost): very large tiles (a
  // whole mm-sized scan) would need thousands of sub-nodes per axis. The raw integral then says
  // how far the table is from resolving D_K, and its warning fires.
  while (s > 1 && s * (resolution - 1) + 1 > 1025) s -= 2;
  return s;
}

KirchhoffAccumulator::KirchhoffAccumulator(const KirchhoffOptions& options)
    : opt_(options), acc_(options.resolution) {
  if (!(opt_.wavelength_q > 0)) throw InputError("Kirchhoff: the wavelength must be > 0");
  if (opt_.resolution < 17) throw InputError("Kirchhoff: resolution must be >= 17");
  if (opt_.supersample != 0 && (opt_.supersample % 2 == 0 || opt_.supersample > 15))
    throw InputError(
        "Kirchhoff: supersample (the node supersampling factor) must be 0 "
        "(automatic) or odd in 1..15, not " +
        std::to_string(opt_.supersample));
}

KirchhoffScanPartial KirchhoffAccumulator::estimate(const Surface& s) const {
  s.check();
  KirchhoffScanPartial r;
  r.table = TabulatedNdf(opt_.resolution);
  r.source = s.meta.source_path;
  r.leveling = s.meta.leveling;
  std::size_t cx, lx, cy, ly;
  tiling(s.nx, s.dx, opt_.patch_x, cx, lx);
  tiling(s.ny, s.dy, opt_.patch_y, cy, ly);
  // A patch of a few samples resolves no slope, and a scan cut into one-sample patches runs a
  // whole D_K table per sample (a 1e-30 m patch once meant hours): at least 4 samples a side.
  constexpr std::size_t kMinPatchSamples = 4;
  if ((cx > 1 && lx < kMinPatchSamples) || (cy > 1 && ly < kMinPatchSamples)) {
    char why[200];
    std::snprintf(why, sizeof why,
                  "Kirchhoff patch %.4g x %.4g um cuts the scan into patches of %zu x %zu samples; "
                  "a patch needs at least %zu samples a side (--patch)",
                  opt_.patch_x * 1e6, opt_.patch_y * 1e6, lx, ly, kMinPatchSamples);
    throw InputError(why);
  }
  char buf[160];
  std::snprintf(buf, sizeof buf, "%zux%zu tiles of %zux%zu samples (%.4g x %.4g um)", cx, cy, lx,
                ly, static_cast<double>(lx) * s.dx * 1e6, static_cast<double>(ly) * s.dy * 1e6);
  r.tiles = buf;
  r.skipped += s.size() - cx * lx * cy * ly;  // margins left out by the tiling
  // Sub-nodes per axis: node values are averages over each node's cell (S odd: the centre
  // sub-node is the node itself, and every sub-node belongs to exactly one cell).
  const std::size_t S = opt_.supersample != 0
                            ? opt_.supersample
                            : kirchhoff_auto_supersample(opt_.resolution, opt_.wavelength_q,
                                                         static_cast<double>(lx) * s.dx,
                                                         static_cast<double>(ly) * s.dy);
  r.supersample = S;
  const std::size_t N = opt_.resolution, NF = S * (N - 1) + 1;
  const KirchhoffIntegration integ = opt_.integration;
  std::vector<std::size_t> all;
  if (opt_.direct) {
    all.resize(NF * NF);
    for (std::size_t i = 0; i < NF * NF; ++i) all[i] = i;
  }
  const double n_tiles = static_cast<double>(cx * cy);
  std::size_t done = 0;
  auto tick = [&] {
    ++done;
    if (opt_.progress) opt_.progress(static_cast<double>(done) / n_tiles);
  };
  if (opt_.progress) opt_.progress(0.0);
  for (std::size_t ty = 0; ty < cy; ++ty)
    for (std::size_t tx = 0; tx < cx; ++tx) {
      KirchhoffPatch p =
          make_kirchhoff_patch(s, tx * lx, ty * ly, lx, ly, opt_.window, opt_.gauss_fraction);
      r.used += p.valid;
      r.skipped += p.invalid;
      const double aw = kirchhoff_area_w2(p, integ);
      if (!(aw > 0)) {
        tick();
        continue;
      }
      std::vector<double> d =
          opt_.direct
              ? kirchhoff_nodes_direct(p, opt_.wavelength_q, NF, all, integ)
              : kirchhoff_table_fast(p, opt_.wavelength_q, NF, opt_.accuracy, &r.info, false, integ,
                                     opt_.nyquist_mask ? M_PI / s.dx : INFINITY,
                                     opt_.nyquist_mask ? M_PI / s.dy : INFINITY);
      r.has_info = r.has_info || !opt_.direct;
      const double del = 2.0 / static_cast<double>(NF - 1);
      if (opt_.nyquist_mask) {
        const double qm = 4 * M_PI / opt_.wavelength_q;
        const double bx = M_PI / s.dx, by = M_PI / s.dy;
        for (std::size_t iy = 0; iy < NF; ++iy)
          for (std::size_t ix = 0; ix < NF; ++ix) {
            double qx = qm * std::fabs(-1 + del * static_cast<double>(ix));
            double qy = qm * std::fabs(-1 + del * static_cast<double>(iy));
            if (qx > bx || qy > by) {
              r.aliased += aw * d[iy * NF + ix] * del * del;
              d[iy * NF + ix] = 0;
            }
          }
      }
      auto& v = r.table.values();
      if (S == 1) {
        for (std::size_t i = 0; i < v.size(); ++i) v[i] += aw * d[i];
      } else {  // cell averages of the S x S sub-nodes about each node
        const auto half = static_cast<std::ptrdiff_t>(S / 2), nf = static_cast<std::ptrdiff_t>(NF);
        const double wgt = aw / static_cast<double>(S * S);
        for (std::size_t iy = 0; iy < N; ++iy)
          for (std::size_t ix = 0; ix < N; ++ix) {
            const auto cx = static_cast<std::ptrdiff_t>(S * ix),
                       cy = static_cast<std::ptrdiff_t>(S * iy);
            double sum = 0;
            for (std::ptrdiff_t fy = std::max<std::ptrdiff_t>(cy - half, 0);
                 fy <= std::min(cy + half, nf - 1); ++fy)
              for (std::ptrdiff_t fx = std::max<std::ptrdiff_t>(cx - half, 0);
                   fx <= std::min(cx + half, nf - 1); ++fx)
                sum += d[static_cast<std::size_t>(fy * nf + fx)];
            v[iy * N + ix] += wgt * sum;
          }
      }
      r.area_w2 += aw;
      r.valid_area += integ == KirchhoffIntegration::Exact ? p.valid_area_tri : p.valid_area;
      ++r.patches;
      tick();
    }
  return r;
}

void KirchhoffAccumulator::merge(const KirchhoffScanPartial& p) {
  if (p.table.resolution() != acc_.resolution())
    throw InputError("Kirchhoff accumulator: a scan's table has the wrong resolution");
  if (!p.source.empty()) sources_.push_back(p.source);
  leveling_ = p.leveling;
  tiles_ = p.tiles;
  auto& v = acc_.values();
  const auto& w = p.table.values();
  for (std::size_t i = 0; i < v.size(); ++i) v[i] += w[i];
  area_w2_ += p.area_w2;
  valid_area_ += p.valid_area;
  aliased_ += p.aliased;
  patches_ += p.patches;
  used_ += p.used;
  skipped_ += p.skipped;
  if (p.has_info) info_ = p.info;
  supersample_ = std::max(supersample_, p.supersample);
}

void KirchhoffAccumulator::add(const Surface& s) { merge(estimate(s)); }

double KirchhoffAccumulator::aliased_fraction() const {
  double kept = acc_.integral();
  return kept + aliased_ > 0 ? aliased_ / (kept + aliased_) : 0.0;
}

double KirchhoffAccumulator::raw_integral() const {
  if (!(area_w2_ > 0)) return 0.0;
  return acc_.integral() / area_w2_;
}

TabulatedNdf KirchhoffAccumulator::result() const {
  if (patches_ == 0 || !(acc_.integral() > 0))
    throw InputError("Kirchhoff: no valid samples were accumulated");
  TabulatedNdf out = acc_;
  out.normalise();
  out.meta.method = "kirchhoff";
  out.meta.wavelength_m = opt_.wavelength_q;
  out.meta.samples_used = used_;
  out.meta.samples_skipped = skipped_;
  out.meta.projected_area_m2 = valid_area_;
  out.meta.sources = sources_;
  out.meta.leveling = leveling_;
  char method[200];
  const bool exact = opt_.integration == KirchhoffIntegration::Exact;
  if (opt_.direct)
    std::snprintf(method, sizeof method, "direct sums");
  else if (exact)
    std::snprintf(method, sizeof method,
                  "fast (Chebyshev series in q_z x NUFFT at the node frequencies, %zu-point rule "
                  "per triangle), accuracy %g, %zu terms",
                  info_.points_per_triangle, opt_.accuracy, info_.terms);
  else
    std::snprintf(method, sizeof method,
                  "fast (Chebyshev series in q_z x NUFFT at the node frequencies), accuracy %g, "
                  "%zu terms",
                  opt_.accuracy, info_.terms);
  char sampling[120];
  if (supersample_ > 1)
    std::snprintf(sampling, sizeof sampling, "node values are cell averages of %zu x %zu sub-nodes",
                  supersample_, supersample_);
  else
    std::snprintf(sampling, sizeof sampling, "node values are point samples");
  char buf[800];
  std::snprintf(buf, sizeof buf,
                "D_K (Dong eq. 6), %s with the (q.m) factor; lambda_q = "
                "%.6g nm; %zu patch(es), last: %s; window %s; %s; %s; integral before "
                "normalising %.6g (Nyquist mask %s, removed %.3g of the mass)",
                exact ? "exact integration over the triangles of the piecewise-linear surface"
                      : "midpoint rule per sample",
                opt_.wavelength_q * 1e9, patches_, tiles_.c_str(), to_string(opt_.window).c_str(),
                method, sampling, raw_integral(), opt_.nyquist_mask ? "on" : "off",
                aliased_fraction());
  out.meta.notes = buf;
  return out;
}

TabulatedNdf estimate_kirchhoff(const Surface& s, const KirchhoffOptions& options) {
  KirchhoffAccumulator acc(options);
  acc.add(s);
  return acc.result();
}

}  // namespace microbrdf
