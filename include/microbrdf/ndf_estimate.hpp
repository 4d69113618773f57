#pragma once
// Geometric NDFs estimated from height maps (Dong 2015 section 5.1, eq. 2; docs/theory.md §2-3).

#include <cstddef>
#include <string>
#include <vector>

#include "microbrdf/surface.hpp"
#include "microbrdf/tabulated_ndf.hpp"

namespace microbrdf {

enum class NdfMethod { Naive, Filtered };

struct NdfEstimateOptions {
  NdfMethod method = NdfMethod::Filtered;
  std::size_t resolution = 1025;
  double filter_sigma_m = 1e-6;  ///< Gaussian std of the local plane fit, m (Filtered)
  double truncate_sigmas = 4;    ///< kernel support, in filter sigmas
  /// A filtered sample is used only if its weighted support (the sum of Gaussian weights over
  /// valid neighbours) is at least this fraction of the full-grid value: fits near borders and
  /// holes that see too little surface are skipped and counted (docs/theory.md §3.3).
  double min_support = 0.5;
  /// The square of the disk plane tabulated (default: all of it). A zoomed window resolves a
  /// narrow lobe; normals outside it are not counted (their share of the projected area is
  /// recorded as 1 - meta.window_mass) and the table is normalised over the window.
  NdfWindow window;
};

/// One scan's share of an NdfAccumulator: its own unnormalised table (projected area per node)
/// and counters. Scans are estimated on their own and their shares folded in scan order, so a
/// scan set gives the same table bit for bit wherever and in whatever order its scans were
/// estimated (distribute.hpp).
struct NdfScanPartial {
  TabulatedNdf table;
  NdfMetadata meta;  ///< samples_used, samples_skipped, projected_area_m2, sources, leveling
};

/// Accumulates normals of many scans, weighted by projected area, into one NDF; memory is one
/// table however many scans are added.
class NdfAccumulator {
 public:
  explicit NdfAccumulator(const NdfEstimateOptions& options);
  /// Adds one scan (levelled as the caller wants; a residual tilt shifts the NDF):
  /// merge(estimate(s)).
  void add(const Surface& s);
  /// One scan's share, computed without touching the accumulator (any thread or rank).
  NdfScanPartial estimate(const Surface& s) const;
  /// Folds one scan's share in (table sum node by node, counters, sources).
  void merge(const NdfScanPartial& p);
  /// The same, taking the share's table over when it is the first (no copy, no sum).
  void merge(NdfScanPartial&& p);
  /// The normalised NDF of everything added. Throws InputError if nothing was accumulated.
  TabulatedNdf result() const&;
  /// The same, normalising the accumulator's own table in place (the accumulator is spent).
  TabulatedNdf result() &&;
  const NdfEstimateOptions& options() const { return opt_; }

 private:
  NdfEstimateOptions opt_;
  TabulatedNdf acc_;  ///< 3 x 3 placeholder (with the meta) until the first share
  void check_share(const NdfScanPartial& p) const;
  void take_first(std::vector<double>&& values);
  void merge_meta(const NdfScanPartial& p);
  bool merged_ = false;  ///< a share was folded in (acc_ holds the sum)
};

/// One scan's NDF (NdfAccumulator with a single add).
TabulatedNdf estimate_ndf(const Surface& s, const NdfEstimateOptions& options);

/// Filtered normals: per sample, the normal of the plane fitted by Gaussian-weighted least
/// squares (weights x validity). Computed with separable correlations of masked moment images
/// (O(N K)); samples failing the support rule are (0,0,0).
struct NormalField {
  std::size_t nx = 0, ny = 0;
  std::vector<double> mx, my, mz;  ///< unit normal components; all 0 where skipped
  std::size_t used = 0, skipped = 0;
};
NormalField filtered_normals(const Surface& s, double filter_sigma, double truncate_sigmas = 4,
                             double min_support = 0.5);

/// Brute-force reference of filtered_normals at one sample: the same weighted least-squares
/// plane fit summed directly over the kernel support. Returns false if skipped.
bool filtered_normal_direct(const Surface& s, std::size_t ix, std::size_t iy, double filter_sigma,
                            double truncate_sigmas, double min_support, double out[3]);

}  // namespace microbrdf
