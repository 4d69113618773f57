// Histogram NDF estimators (Dong 2015 eq. 2; docs/theory.md §2.2): every element's normal is
// splatted bilinearly onto the disk grid with its projected area, so the normalisation is exact
// at any resolution and scans of different spacings combine by projected area.
#include "microbrdf/ndf_estimate.hpp"

#include <cmath>

#include "microbrdf/error.hpp"

namespace microbrdf {

NdfAccumulator::NdfAccumulator(const NdfEstimateOptions& options)
    : opt_(options), acc_(options.resolution) {
  acc_.meta.method = options.method == NdfMethod::Naive ? "naive" : "filtered";
  acc_.meta.filter_sigma_m = options.method == NdfMethod::Filtered ? options.filter_sigma_m : 0.0;
}

namespace {

// Naive: two triangles per grid cell, split along the diagonal (ix, iy)-(ix+1, iy+1).
// Lower triangle (00, 10, 11): dz/dx = (z10 - z00)/dx, dz/dy = (z11 - z10)/dy.
// Upper triangle (00, 11, 01): dz/dx = (z11 - z01)/dx, dz/dy = (z01 - z00)/dy.
void add_naive(const Surface& s, TabulatedNdf& acc, NdfMetadata& meta) {
  const double area = 0.5 * s.dx * s.dy;
  for (std::size_t iy = 0; iy + 1 < s.ny; ++iy)
    for (std::size_t ix = 0; ix + 1 < s.nx; ++ix) {
      const std::size_t i00 = iy * s.nx + ix, i10 = i00 + 1, i01 = i00 + s.nx, i11 = i01 + 1;
      const bool v00 = s.valid[i00], v10 = s.valid[i10], v01 = s.valid[i01], v11 = s.valid[i11];
      auto splat = [&](double gx, double gy) {
        double inv = 1.0 / std::sqrt(1.0 + gx * gx + gy * gy);
        acc.splat(-gx * inv, -gy * inv, area);
        ++meta.samples_used;
        meta.projected_area_m2 += area;
      };
      if (v00 && v10 && v11)
        splat((s.z[i10] - s.z[i00]) / s.dx, (s.z[i11] - s.z[i10]) / s.dy);
      else
        ++meta.samples_skipped;
      if (v00 && v11 && v01)
        splat((s.z[i11] - s.z[i01]) / s.dx, (s.z[i01] - s.z[i00]) / s.dy);
      else
        ++meta.samples_skipped;
    }
}

void add_filtered(const Surface& s, const NdfEstimateOptions& o, TabulatedNdf& acc,
                  NdfMetadata& meta) {
  auto f = filtered_normals(s, o.filter_sigma_m, o.truncate_sigmas, o.min_support);
  const double area = s.dx * s.dy;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (f.mz[i] > 0) acc.splat(f.mx[i], f.my[i], area);
  meta.samples_used += f.used;
  meta.samples_skipped += f.skipped;
  meta.projected_area_m2 += area * static_cast<double>(f.used);
}

}  // namespace

NdfScanPartial NdfAccumulator::estimate(const Surface& s) const {
  NdfScanPartial p{TabulatedNdf(opt_.resolution), {}};
  if (opt_.method == NdfMethod::Naive)
    add_naive(s, p.table, p.meta);
  else
    add_filtered(s, opt_, p.table, p.meta);
  if (!s.meta.source_path.empty()) p.meta.sources.push_back(s.meta.source_path);
  p.meta.leveling = s.meta.leveling;
  return p;
}

void NdfAccumulator::merge(const NdfScanPartial& p) {
  if (p.table.resolution() != acc_.resolution())
    throw InputError("NDF accumulator: a scan's table has resolution " +
                     std::to_string(p.table.resolution()) + ", expected " +
                     std::to_string(acc_.resolution()));
  auto& v = acc_.values();
  const auto& w = p.table.values();
  for (std::size_t i = 0; i < v.size(); ++i) v[i] += w[i];
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

TabulatedNdf NdfAccumulator::result() const {
  if (!(acc_.meta.projected_area_m2 > 0)) {
    const char* why =
        "no normal could be estimated (every element touches an invalid sample or lacks support)";
    if (acc_.meta.sources.empty()) throw InputError(why);
    // The scans are the problem: name them (the first few).
    std::string names;
    for (std::size_t i = 0; i < acc_.meta.sources.size() && i < 3; ++i)
      names += (i ? ", " : "") + acc_.meta.sources[i];
    if (acc_.meta.sources.size() > 3) names += ", ...";
    throw FileError(names, why);
  }
  TabulatedNdf out = acc_;
  // Rim splats can reach nodes just outside the unit disk, where D is 0 by convention.
  out.clear_outside_disk();
  out.normalise();
  return out;
}

TabulatedNdf estimate_ndf(const Surface& s, const NdfEstimateOptions& options) {
  NdfAccumulator a(options);
  a.add(s);
  return a.result();
}

}  // namespace microbrdf
