// Histogram NDF estimators (Dong 2015 eq. 2; docs/theory.md §2.2): every element's normal is
// splatted bilinearly onto the disk grid with its projected area, so the normalisation is exact
// at any resolution and scans of different spacings combine by projected area.
#include "microbrdf/ndf_estimate.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/helper_pool.hpp"
#include "microbrdf/error.hpp"
#include "ndf/filtered_normals_core.hpp"

namespace microbrdf {

NdfAccumulator::NdfAccumulator(const NdfEstimateOptions& options)
    : opt_(options), acc_(3, options.window) {  // a placeholder until the first share
  // (The table's own check, made here rather than at the first share.)
  if (options.resolution < 3) throw std::invalid_argument("TabulatedNdf: resolution must be >= 3");
  acc_.meta.method = options.method == NdfMethod::Naive ? "naive" : "filtered";
  acc_.meta.sampling = "cell";
  acc_.meta.filter_sigma_m = options.method == NdfMethod::Filtered ? options.filter_sigma_m : 0.0;
}

namespace {

// Naive: two triangles per grid cell, split along the diagonal (ix, iy)-(ix+1, iy+1).
// Lower triangle (00, 10, 11): dz/dx = (z10 - z00)/dx, dz/dy = (z11 - z10)/dy.
// Upper triangle (00, 11, 01): dz/dx = (z11 - z01)/dx, dz/dy = (z01 - z00)/dy.
// Facet normals of the cells' two triangles, a band of scan rows at a time into two reused
// per-thread buffers (NaN = a triangle touching an invalid sample), rows on the helper threads,
// then splatted in cell order: the same table, bit for bit, as one splat per triangle in a plain
// loop, whatever the thread count.
void add_naive(const Surface& s, TabulatedNdf& acc, NdfMetadata& meta) {
  if (s.nx < 2 || s.ny < 2) return;
  const double area = 0.5 * s.dx * s.dy;
  const int threads = omp_get_max_threads();
  const std::size_t per_row = 2 * (s.nx - 1);
  const std::size_t band = std::max<std::size_t>(1, (std::size_t{1} << 18) / per_row);
  double* mx = detail::thread_scratch(band * per_row, 0);
  double* my = detail::thread_scratch(band * per_row, 1);
  std::vector<std::size_t> used_in_row(s.ny, 0);
  for (std::size_t y0 = 0; y0 + 1 < s.ny; y0 += band) {
    const std::size_t rows = std::min(band, s.ny - 1 - y0);
    const std::function<void(std::size_t)> row = [&](std::size_t r) {
      const std::size_t iy = y0 + r;
      double* ox = mx + r * per_row;
      double* oy = my + r * per_row;
      std::size_t used = 0;
      auto normal = [&](std::size_t k, bool ok, double gx, double gy) {
        if (!ok) {
          ox[k] = std::numeric_limits<double>::quiet_NaN();
          return;
        }
        const double inv = 1.0 / std::sqrt(1.0 + gx * gx + gy * gy);
        ox[k] = -gx * inv;
        oy[k] = -gy * inv;
        ++used;
      };
      for (std::size_t ix = 0; ix + 1 < s.nx; ++ix) {
        const std::size_t i00 = iy * s.nx + ix, i10 = i00 + 1, i01 = i00 + s.nx, i11 = i01 + 1;
        const bool v00 = s.valid[i00], v10 = s.valid[i10], v01 = s.valid[i01], v11 = s.valid[i11];
        normal(2 * ix, v00 && v10 && v11, (s.z[i10] - s.z[i00]) / s.dx,
               (s.z[i11] - s.z[i10]) / s.dy);
        normal(2 * ix + 1, v00 && v11 && v01, (s.z[i11] - s.z[i01]) / s.dx,
               (s.z[i01] - s.z[i00]) / s.dy);
      }
      used_in_row[iy] = used;
    };
    detail::HelperPool::instance().run(rows, threads, row);
    detail::splat_normals(mx, my, rows * per_row, area, acc, threads);
  }
  std::size_t used = 0;
  for (std::size_t u : used_in_row) used += u;
  meta.samples_used += used;
  meta.samples_skipped += per_row * (s.ny - 1) - used;
  meta.projected_area_m2 += area * static_cast<double>(used);
}

// Normals into two reused per-thread buffers (16 bytes per point, NaN = no normal), then splatted
// in point order (the same table, bit for bit, as one splat per point in a plain loop).
void add_filtered(const Surface& s, const NdfEstimateOptions& o, TabulatedNdf& acc,
                  NdfMetadata& meta) {
  double* mx = detail::thread_scratch(s.size(), 0);
  double* my = detail::thread_scratch(s.size(), 1);
  std::size_t used = 0, skipped = 0;
  detail::filtered_normals_into(s, o.filter_sigma_m, o.truncate_sigmas, o.min_support, mx, my,
                                nullptr, used, skipped);
  const double area = s.dx * s.dy;
  detail::splat_normals(mx, my, s.size(), area, acc, omp_get_max_threads());
  meta.samples_used += used;
  meta.samples_skipped += skipped;
  meta.projected_area_m2 += area * static_cast<double>(used);
}

NdfScanPartial estimate_partial(const Surface& s, const NdfEstimateOptions& opt) {
  NdfScanPartial p{TabulatedNdf(opt.resolution, opt.window), {}};
  if (opt.method == NdfMethod::Naive)
    add_naive(s, p.table, p.meta);
  else
    add_filtered(s, opt, p.table, p.meta);
  if (!s.meta.source_path.empty()) p.meta.sources.push_back(s.meta.source_path);
  p.meta.leveling = s.meta.leveling;
  return p;
}

// The normalised table of an accumulator's sum `t` (its meta already merged).
TabulatedNdf finalise(TabulatedNdf t) {
  if (!(t.meta.projected_area_m2 > 0)) {
    const char* why =
        "no normal could be estimated (every element touches an invalid sample or lacks support)";
    if (t.meta.sources.empty()) throw InputError(why);
    // The scans are the problem: name them (the first few).
    std::string names;
    for (std::size_t i = 0; i < t.meta.sources.size() && i < 3; ++i)
      names += (i ? ", " : "") + t.meta.sources[i];
    if (t.meta.sources.size() > 3) names += ", ...";
    throw FileError(names, why);
  }
  // Every splat keeps its weight (projected area) on the nodes when it lands inside the table's
  // square: the node sum over the projected area is the share inside a zoomed window.
  if (!t.window().full()) {
    double inside = 0;
    for (double v : t.values()) inside += v;
    t.meta.window_mass = std::min(1.0, inside / t.meta.projected_area_m2);
    if (!(inside > 0))
      throw InputError("no normal falls inside the NDF window (centre " +
                       std::to_string(t.window().cx) + ", " + std::to_string(t.window().cy) +
                       ", half-width " + std::to_string(t.window().half) +
                       "); widen it or centre it on the lobe");
  }
  // Rim splats can reach nodes just outside the unit disk, where D is 0 by convention.
  t.clear_outside_disk();
  t.normalise();
  return t;
}

}  // namespace

NdfScanPartial NdfAccumulator::estimate(const Surface& s) const {
  return estimate_partial(s, opt_);
}

void NdfAccumulator::check_share(const NdfScanPartial& p) const {
  // (Shares unpacked from other ranks carry no window; they were estimated with this one.)
  if (p.table.resolution() != opt_.resolution)
    throw InputError("NDF accumulator: a scan's table has resolution " +
                     std::to_string(p.table.resolution()) + ", expected " +
                     std::to_string(opt_.resolution));
}

// The accumulator holds no table until the first share: 0 + x == x node by node, so that share's
// table becomes the sum (no N^2 zeros made and thrown away).
void NdfAccumulator::take_first(std::vector<double>&& values) {
  TabulatedNdf t(opt_.resolution, std::move(values), opt_.window);
  t.meta = std::move(acc_.meta);
  acc_ = std::move(t);
}

void NdfAccumulator::merge(const NdfScanPartial& p) {
  check_share(p);
  if (!merged_) {
    take_first(std::vector<double>(p.table.values()));
  } else {
    auto& v = acc_.values();
    const auto& w = p.table.values();
    for (std::size_t i = 0; i < v.size(); ++i) v[i] += w[i];
  }
  merge_meta(p);
}

void NdfAccumulator::merge(NdfScanPartial&& p) {
  if (merged_) return merge(std::as_const(p));
  check_share(p);
  take_first(std::move(p.table.values()));
  merge_meta(p);
}

void NdfAccumulator::merge_meta(const NdfScanPartial& p) {
  merged_ = true;
  acc_.meta.samples_used += p.meta.samples_used;
  acc_.meta.samples_skipped += p.meta.samples_skipped;
  acc_.meta.projected_area_m2 += p.meta.projected_area_m2;
  for (const auto& src : p.meta.sources) acc_.meta.sources.push_back(src);
  if (acc_.meta.leveling.empty())
    acc_.meta.leveling = p.meta.leveling;
  else if (acc_.meta.leveling != p.meta.leveling)
    acc_.meta.leveling = "mixed";
}

void NdfAccumulator::add(const Surface& s) { merge(estimate(s)); }

TabulatedNdf NdfAccumulator::result() const& { return finalise(acc_); }

TabulatedNdf NdfAccumulator::result() && { return finalise(std::move(acc_)); }

TabulatedNdf estimate_ndf(const Surface& s, const NdfEstimateOptions& options) {
  // One scan: its share is the sum (0 + x == x), so it is finalised in place, without the
  // accumulator's own table and copy.
  NdfScanPartial p = estimate_partial(s, options);
  TabulatedNdf& t = p.table;
  t.meta.method = options.method == NdfMethod::Naive ? "naive" : "filtered";
  t.meta.sampling = "cell";
  t.meta.filter_sigma_m = options.method == NdfMethod::Filtered ? options.filter_sigma_m : 0.0;
  t.meta.samples_used = p.meta.samples_used;
  t.meta.samples_skipped = p.meta.samples_skipped;
  t.meta.projected_area_m2 = p.meta.projected_area_m2;
  t.meta.sources = p.meta.sources;
  t.meta.leveling = p.meta.leveling;
  return finalise(std::move(t));
}

}  // namespace microbrdf
