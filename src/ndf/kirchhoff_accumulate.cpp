// Kirchhoff distribution of scans and scan sets: tiling into coherence-area patches and
// intensity averaging (Dong 2015 App. A; docs/theory.md §4.5).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <type_traits>

#include "microbrdf/error.hpp"
#include "microbrdf/kirchhoff.hpp"
#include "microbrdf/memory_budget.hpp"

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

// Sum of value(i) over the sub-nodes of node (ix, iy)'s cell on a grid of nf x nf sub-nodes,
// S per node (S odd: the centre sub-node is the node; cells are clipped at the grid's edge).
template <class Value>
double cell_sum(std::size_t ix, std::size_t iy, std::size_t S, std::size_t nf, Value value) {
  const auto half = static_cast<std::ptrdiff_t>(S / 2), n = static_cast<std::ptrdiff_t>(nf);
  const auto cx = static_cast<std::ptrdiff_t>(S * ix), cy = static_cast<std::ptrdiff_t>(S * iy);
  double sum = 0;
  for (std::ptrdiff_t fy = std::max<std::ptrdiff_t>(cy - half, 0); fy <= std::min(cy + half, n - 1);
       ++fy)
    for (std::ptrdiff_t fx = std::max<std::ptrdiff_t>(cx - half, 0);
         fx <= std::min(cx + half, n - 1); ++fx)
      sum += value(static_cast<std::size_t>(fy * n + fx));
  return sum;
}

}  // namespace

std::vector<double> kirchhoff_stack_wavelengths(double lo, double hi) {
  if (!(lo > 0) || !(hi >= lo)) throw InputError("Kirchhoff stack: need 0 < lo <= hi");
  // Geometric steps: D_K at a fixed half-vector changes with lambda_q through |q| = 4 pi /
  // lambda_q, smoothly in log |q| (power-law spectra are straight lines there); the BRDF
  // interpolates log D_K cubically in log lambda_q between these layers.
  const double top = kKirchhoffStackSpan * hi;
  const auto steps = static_cast<std::size_t>(
      std::ceil(std::log(top / lo) / std::log(kKirchhoffStackRatio) - 1e-9));
  std::vector<double> out;
  for (std::size_t i = 0; i <= steps; ++i)
    out.push_back(lo * std::pow(top / lo, static_cast<double>(i) / static_cast<double>(steps)));
  return out;
}

std::vector<double> kirchhoff_stack_layers(const std::string& stack, double lambda) {
  std::vector<double> all;
  if (stack == "visible")
    all = kirchhoff_stack_wavelengths(std::min(lambda, kKirchhoffVisibleLo),
                                      std::max(lambda, kKirchhoffVisibleHi));
  else if (stack == "wavelength")
    all = kirchhoff_stack_wavelengths(lambda, lambda);
  else if (stack != "single")
    throw InputError("the D_K stack must be visible, wavelength or single, not '" + stack + "'");
  // The table at --wavelength is the primary one; layers within 1 % of it would only repeat it.
  std::vector<double> out;
  for (double l : all)
    if (std::fabs(l / lambda - 1) > 0.01) out.push_back(l);
  return out;
}

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

KirchhoffAccumulator::KirchhoffAccumulator(const KirchhoffOptions& options) : opt_(options) {
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
  const std::size_t N = opt_.resolution;
  const KirchhoffIntegration integ = opt_.integration;
  // The layers: the table at wavelength_q and the stack over lambda_q, all from the same tiles.
  std::vector<double> lqs{opt_.wavelength_q};
  lqs.insert(lqs.end(), opt_.stack_wavelengths_q.begin(), opt_.stack_wavelengths_q.end());
  // Each layer's sum over the tiles, made from its first tile's table (not allocated as zeros
  // beforehand: with the stack that was 12 tables of 8.4 MB before any work).
  std::vector<std::optional<TabulatedNdf>> sums(lqs.size());
  r.stack_aliased.assign(opt_.stack_wavelengths_q.size(), 0.0);
  r.coherent.assign(lqs.size(), {});
  std::vector<std::size_t> subnodes(lqs.size());
  for (std::size_t l = 0; l < lqs.size(); ++l) {
    // Sub-nodes per axis: node values are averages over each node's cell (S odd: the centre
    // sub-node is the node itself, and every sub-node belongs to exactly one cell).
    subnodes[l] = opt_.supersample != 0
                      ? opt_.supersample
                      : kirchhoff_auto_supersample(N, lqs[l], static_cast<double>(lx) * s.dx,
                                                   static_cast<double>(ly) * s.dy);
  }
  r.supersample = subnodes[0];  // the table at wavelength_q (the stack's layers may differ)
  // What the scan's share holds beyond one table: the stack's tables and, per layer, the mean
  // field on its sub-node grid (16 bytes a sub-node).
  {
    double bytes = 8.0 * static_cast<double>(N * N) * static_cast<double>(lqs.size() - 1);
    if (opt_.separate_specular && !opt_.direct && cx * cy >= kKirchhoffMinTilesCoherent)
      for (std::size_t S : subnodes) {
        const double nf = static_cast<double>(S * (N - 1) + 1);
        bytes += 16.0 * nf * nf;
      }
    check_memory(s.meta.source_path, static_cast<std::uint64_t>(std::min(bytes, 1.8e19)),
                 "the D_K tables over lambda_q and their mean fields");
  }
  const double n_steps = static_cast<double>(cx * cy * lqs.size());
  std::size_t done = 0;
  auto tick = [&](std::size_t steps) {
    done += steps;
    if (opt_.progress) opt_.progress(static_cast<double>(done) / n_steps);
  };
  if (opt_.progress) opt_.progress(0.0);
  // One tile's A_w D_K at lambda_q added to `table` (node averages of S x S sub-nodes).
  auto add_layer = [&](const KirchhoffPatch& p, double aw, double lambda_q, std::size_t S,
                       std::optional<TabulatedNdf>& table, double& aliased, KirchhoffFastInfo* info,
                       std::vector<std::complex<double>>& coherent) {
    // The mean field needs the amplitudes of point-sampled nodes from the fast method.
    const bool keep =
        opt_.separate_specular && !opt_.direct && cx * cy >= kKirchhoffMinTilesCoherent;
    std::vector<std::complex<double>> amp;
    const std::size_t NF = S * (N - 1) + 1;
    std::vector<std::size_t> all;
    if (opt_.direct) {
      all.resize(NF * NF);
      for (std::size_t i = 0; i < NF * NF; ++i) all[i] = i;
    }
    std::vector<double> d =
        opt_.direct ? kirchhoff_nodes_direct(p, lambda_q, NF, all, integ)
                    : kirchhoff_table_fast(p, lambda_q, NF, opt_.accuracy, info, false, integ,
                                           opt_.nyquist_mask ? M_PI / s.dx : INFINITY,
                                           opt_.nyquist_mask ? M_PI / s.dy : INFINITY,
                                           keep ? &amp : nullptr);
    r.has_info = r.has_info || !opt_.direct;
    const double del = 2.0 / static_cast<double>(NF - 1);
    if (opt_.nyquist_mask) {
      const double qm = 4 * M_PI / lambda_q;
      const double bx = M_PI / s.dx, by = M_PI / s.dy;
      for (std::size_t iy = 0; iy < NF; ++iy)
        for (std::size_t ix = 0; ix < NF; ++ix) {
          double qx = qm * std::fabs(-1 + del * static_cast<double>(ix));
          double qy = qm * std::fabs(-1 + del * static_cast<double>(iy));
          if (qx > bx || qy > by) {
            aliased += aw * d[iy * NF + ix] * del * del;
            d[iy * NF + ix] = 0;
            if (keep) amp[iy * NF + ix] = 0;
          }
        }
    }
    if (keep) {
      if (coherent.empty()) coherent.assign(NF * NF, {0.0, 0.0});
      const double sw = std::sqrt(aw);
      for (std::size_t i = 0; i < amp.size(); ++i) coherent[i] += sw * amp[i];
    }
    if (!table && S == 1) {  // the first tile: its table is the sum (0 + aw d = aw d, d >= 0)
      for (double& x : d) x *= aw;
      table.emplace(N, std::move(d));
      return;
    }
    if (!table) table.emplace(N);
    auto& v = table->values();
    if (S == 1) {
      for (std::size_t i = 0; i < v.size(); ++i) v[i] += aw * d[i];
      return;
    }
    const double wgt = aw / static_cast<double>(S * S);
    for (std::size_t iy = 0; iy < N; ++iy)
      for (std::size_t ix = 0; ix < N; ++ix)
        v[iy * N + ix] += wgt * cell_sum(ix, iy, S, NF, [&](std::size_t i) { return d[i]; });
  };
  for (std::size_t ty = 0; ty < cy; ++ty)
    for (std::size_t tx = 0; tx < cx; ++tx) {
      KirchhoffPatch p =
          make_kirchhoff_patch(s, tx * lx, ty * ly, lx, ly, opt_.window, opt_.gauss_fraction);
      r.used += p.valid;
      r.skipped += p.invalid;
      const double aw = kirchhoff_area_w2(p, integ);
      if (!(aw > 0)) {
        tick(lqs.size());
        continue;
      }
      for (std::size_t l = 0; l < lqs.size(); ++l) {
        KirchhoffFastInfo layer_info;  // the report describes the table at wavelength_q
        if (l == 0)
          add_layer(p, aw, lqs[0], subnodes[0], sums[0], r.aliased, &r.info, r.coherent[0]);
        else
          add_layer(p, aw, lqs[l], subnodes[l], sums[l], r.stack_aliased[l - 1], &layer_info,
                    r.coherent[l]);
        tick(1);
      }
      r.area_w2 += aw;
      r.valid_area += integ == KirchhoffIntegration::Exact ? p.valid_area_tri : p.valid_area;
      ++r.patches;
    }
  // (A layer no tile reached is a table of zeros.)
  r.table = sums[0] ? std::move(*sums[0]) : TabulatedNdf(N);
  r.stack.clear();
  for (std::size_t l = 1; l < sums.size(); ++l)
    r.stack.push_back(sums[l] ? std::move(*sums[l]) : TabulatedNdf(N));
  return r;
}

void KirchhoffAccumulator::merge(const KirchhoffScanPartial& p) { merge_impl(p); }

void KirchhoffAccumulator::merge(KirchhoffScanPartial&& p) { merge_impl(std::move(p)); }

// Tables are allocated by the first share, not by the constructor: a share passed as an rvalue
// gives its tables (0 + x = x: the sums are the same bits either way; D_K >= 0, so no -0.0).
template <class Partial>
void KirchhoffAccumulator::merge_impl(Partial&& p) {
  constexpr bool movable = !std::is_lvalue_reference_v<Partial>;
  if (p.table.resolution() != opt_.resolution)
    throw InputError("Kirchhoff accumulator: a scan's table has the wrong resolution");
  if (p.stack.size() != opt_.stack_wavelengths_q.size() || p.stack_aliased.size() != p.stack.size())
    throw InputError("Kirchhoff accumulator: a scan's share has the wrong number of lambda_q");
  for (const auto& t : p.stack)
    if (t.resolution() != opt_.resolution)
      throw InputError("Kirchhoff accumulator: a scan's table has the wrong resolution");
  if (p.coherent.size() != p.stack.size() + 1)
    throw InputError("Kirchhoff accumulator: a scan's share has the wrong number of mean fields");
  // (Everything is checked before anything is taken or added.)
  if (!p.source.empty()) sources_.push_back(p.source);
  leveling_ = p.leveling;
  tiles_ = p.tiles;
  auto add = [](TabulatedNdf& to, const TabulatedNdf& from) {
    auto& v = to.values();
    const auto& w = from.values();
    for (std::size_t i = 0; i < v.size(); ++i) v[i] += w[i];
  };
  if (!acc_) {
    if constexpr (movable)
      acc_.emplace(std::move(p.table));
    else
      acc_.emplace(p.table);
  } else {
    add(*acc_, p.table);
  }
  const bool first_stack = stack_.empty();
  if (first_stack) {
    if constexpr (movable)
      stack_ = std::move(p.stack);
    else
      stack_ = p.stack;
    stack_aliased_.assign(stack_.size(), 0.0);
  }
  // Coherent sums add like the tables; a scan without them (too few tiles) leaves the layer
  // without a mean field (its tiles' amplitudes are not known).
  if (coherent_.empty()) coherent_.assign(p.coherent.size(), {});
  for (std::size_t l = 0; l < p.coherent.size(); ++l) {
    if (p.coherent[l].empty()) {
      coherent_[l].clear();
      coherent_missing_ = true;
      continue;
    }
    if (coherent_missing_) continue;
    if (coherent_[l].empty()) {
      // The first share's mean field becomes the sum (only |sum|^2 and its peak are used, so a
      // -0.0 kept instead of 0 + -0.0 changes nothing).
      if constexpr (movable)
        coherent_[l] = std::move(p.coherent[l]);
      else
        coherent_[l] = p.coherent[l];
      continue;
    }
    if (coherent_[l].size() != p.coherent[l].size())
      throw InputError("Kirchhoff accumulator: a scan's mean field has the wrong size");
    for (std::size_t i = 0; i < p.coherent[l].size(); ++i) coherent_[l][i] += p.coherent[l][i];
  }
  for (std::size_t l = 0; l < stack_aliased_.size(); ++l) {
    if (!first_stack) add(stack_[l], p.stack[l]);
    stack_aliased_[l] += p.stack_aliased[l];
  }
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
  const double kept = acc_ ? acc_->integral() : 0.0;
  return kept + aliased_ > 0 ? aliased_ / (kept + aliased_) : 0.0;
}

double KirchhoffAccumulator::raw_integral() const {
  if (!(area_w2_ > 0) || !acc_) return 0.0;
  return acc_->integral() / area_w2_;
}

TabulatedNdf KirchhoffAccumulator::result() const {
  if (!acc_) throw InputError("Kirchhoff: no valid samples were accumulated");
  return labelled(*acc_, opt_.wavelength_q, aliased_, coherent_of(0));
}

std::vector<TabulatedNdf> KirchhoffAccumulator::stack_result() const {
  std::vector<TabulatedNdf> out{result()};
  for (std::size_t l = 0; l < stack_.size(); ++l)
    out.push_back(
        labelled(stack_[l], opt_.stack_wavelengths_q[l], stack_aliased_[l], coherent_of(l + 1)));
  std::stable_sort(out.begin(), out.end(), [](const TabulatedNdf& a, const TabulatedNdf& b) {
    return a.meta.wavelength_m < b.meta.wavelength_m;
  });
  return out;
}

const std::vector<std::complex<double>>& KirchhoffAccumulator::coherent_of(std::size_t l) const {
  static const std::vector<std::complex<double>> none;
  if (coherent_missing_ || l >= coherent_.size()) return none;
  return coherent_[l];
}

namespace {

// The diffuse part (P/(P-1)) (sum |I_p|^2 - |sum I_p|^2 / P) of the intensity sums, and the
// coherent energy (the rest) put on the node where the mean field peaks (Beckmann and
// Spizzichino's coherent + incoherent split, the mean over tiles standing for the ensemble
// mean). Returns the coherent share of the total, or -1 when the mean field is no larger than
// the tiles' random sum would make it (nothing separated).
double separate_specular(TabulatedNdf& t, const std::vector<std::complex<double>>& m,
                         std::size_t patches) {
  auto& v = t.values();
  const std::size_t N = t.resolution();
  // The mean field is kept on the sub-node grid of S x S sub-nodes per node (NF = S (N-1) + 1);
  // |mean I|^2 is averaged over each node's cell like the intensities.
  const auto nf = static_cast<std::size_t>(std::llround(std::sqrt(static_cast<double>(m.size()))));
  if (patches < 2 || nf * nf != m.size() || nf < N || (nf - 1) % (N - 1) != 0) return 0;
  const std::size_t S = (nf - 1) / (N - 1);
  const double p = static_cast<double>(patches), total = t.integral();
  // Cell averages of |sum I_p|^2 first: without a coherent part (a rough surface) their integral
  // over P is about total / P (the tiles' fields add at random), and taking it out would only
  // put a random share of the energy on one node. The split is made when the mean field holds
  // more than twice that.
  std::vector<double> cm(v.size());
  double coherent_est = 0;
  for (std::size_t iy = 0; iy < N; ++iy)
    for (std::size_t ix = 0; ix < N; ++ix) {
      double c = cell_sum(ix, iy, S, nf, [&](std::size_t i) { return std::norm(m[i]); });
      c /= static_cast<double>(S * S);
      cm[iy * N + ix] = c;
      coherent_est += c / p;
    }
  const double cell = (2.0 / static_cast<double>(N - 1)) * (2.0 / static_cast<double>(N - 1));
  if (!(coherent_est * cell > 2 * total / p)) return -1;
  std::size_t peak = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (cm[i] > cm[peak]) peak = i;
    v[i] = std::max(0.0, v[i] - cm[i] / p) * p / (p - 1);
  }
  const double diffuse = t.integral();
  const double coherent = std::max(0.0, total - diffuse);
  v[peak] += coherent / cell;
  return total > 0 ? coherent / total : 0;
}

}  // namespace

TabulatedNdf KirchhoffAccumulator::labelled(
    const TabulatedNdf& sum, double lambda_q, double aliased,
    const std::vector<std::complex<double>>& coherent) const {
  if (patches_ == 0 || !(sum.integral() > 0))
    throw InputError("Kirchhoff: no valid samples were accumulated");
  TabulatedNdf out = sum;
  const double specular = separate_specular(out, coherent, patches_);
  out.normalise();
  out.meta.method = "kirchhoff";
  out.meta.wavelength_m = lambda_q;
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
  char spec[200];
  if (!coherent.empty() && specular < 0)
    std::snprintf(spec, sizeof spec,
                  "no specular part separated (the mean field over the tiles is within twice "
                  "what random phases give)");
  else if (!coherent.empty())
    std::snprintf(spec, sizeof spec,
                  "specular part (the mean field over the tiles, %.4g of the energy) on its peak "
                  "node",
                  specular);
  else
    std::snprintf(spec, sizeof spec, "specular part not separated%s",
                  !opt_.separate_specular ? " (asked)"
                  : opt_.direct           ? " (direct sums)"
                                          : " (needs at least 8 tiles in every scan)");
  char buf[1000];
  std::snprintf(buf, sizeof buf,
                "D_K (Dong eq. 6), %s with the (q.m) factor; lambda_q = "
                "%.6g nm; %zu patch(es), last: %s; window %s; %s; %s; %s; integral before "
                "normalising %.6g (Nyquist mask %s, removed %.3g of the mass)",
                exact ? "exact integration over the triangles of the piecewise-linear surface"
                      : "midpoint rule per sample",
                lambda_q * 1e9, patches_, tiles_.c_str(), to_string(opt_.window).c_str(), method,
                sampling, spec, area_w2_ > 0 ? sum.integral() / area_w2_ : 0.0,
                opt_.nyquist_mask ? "on" : "off",
                sum.integral() + aliased > 0 ? aliased / (sum.integral() + aliased) : 0.0);
  out.meta.notes = buf;
  return out;
}

TabulatedNdf estimate_kirchhoff(const Surface& s, const KirchhoffOptions& options) {
  KirchhoffAccumulator acc(options);
  acc.add(s);
  return acc.result();
}

}  // namespace microbrdf
