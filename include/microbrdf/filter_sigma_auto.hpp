#pragma once
// `--filter-sigma auto`: the filter sigma at which the filtered NDF (Dong 2015 section 5.1)
// best matches the Kirchhoff distribution D_K at lambda_q (section 6), by the Hellinger distance
// between the two tables over a sweep of sigma (docs/guide.md §7, docs/validation.md §6).
//
// The sweep: `coarse_points` sigmas log-spaced from the sample spacing (the larger of dx, dy) to
// the smaller of `field_fraction` x the shorter side of the scan and `max_spacings` x the
// spacing (a filter wider than that costs O(sigma) per sample and sees mostly the scan's form),
// then `refine_points` more, log-spaced between the coarse neighbours of the coarse minimum.
// The chosen sigma is the one of smallest distance among all evaluated. The sweep runs at a
// small table resolution (257 by default): D_K is the slow part and the distance of lobes
// many nodes wide hardly changes with the table. Range and spacing come from the first scan.

#include <cstddef>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "microbrdf/io.hpp"
#include "microbrdf/kirchhoff.hpp"
#include "microbrdf/level.hpp"
#include "microbrdf/surface.hpp"
#include "microbrdf/tabulated_ndf.hpp"

namespace microbrdf {

/// Hellinger distance between two NDF tables of the same resolution, in [0, 1]:
///   H^2 = 1 - sum_i sqrt(p_i q_i),   p_i = D_a,i Delta^2 / sum_j D_a,j Delta^2
/// (and q_i likewise), the probabilities of the nodes under D(m)(m.n) dw, which on the projected
/// disk is dm_x dm_y. 0 for equal tables, 1 for tables with no node in common. Throws
/// std::invalid_argument for different resolutions and InputError for an empty table.
double hellinger_distance(const TabulatedNdf& a, const TabulatedNdf& b);

struct FilterSigmaPoint {
  double sigma_m = 0;    ///< filter sigma, m
  double hellinger = 0;  ///< Hellinger distance of the filtered NDF at sigma to D_K
};

struct FilterSigmaAutoOptions {
  std::size_t resolution = 257;  ///< table size of the sweep (D_K and every filtered NDF)
  /// D_K settings (wavelength_q, patch, window, accuracy, mask); its resolution is replaced by
  /// `resolution`. The CLI keeps the default midpoint rule here: the sweep compares shapes on
  /// small tables, and the exact triangle rule costs 20-60x more, growing with the phase span
  /// per triangle on coarse or steep scans (docs/kirchhoff.md).
  KirchhoffOptions kirchhoff;
  double truncate_sigmas = 4, min_support = 0.5;  ///< filtered NDF settings (ndf_estimate.hpp)
  double sigma_min_m = 0;  ///< lower end of the sweep; 0 = the sample spacing
  double sigma_max_m = 0;  ///< upper end; 0 = min(field_fraction x field, max_spacings x spacing)
  double field_fraction = 0.125;
  double max_spacings = 128;
  std::size_t coarse_points = 13;
  std::size_t refine_points = 6;
  /// Progress lines (one per pass); empty = silent.
  std::function<void(const std::string&)> log;
};

struct FilterSigmaAuto {
  double sigma_m = 0;                       ///< the chosen sigma (smallest distance on the curve)
  double hellinger = 0;                     ///< its distance to D_K
  std::vector<FilterSigmaPoint> curve;      ///< every sigma evaluated, ascending
  double sigma_min_m = 0, sigma_max_m = 0;  ///< the sweep's range
  std::size_t resolution = 0;
  double wavelength_q_m = 0;
  /// The minimum lies at an end of the sweep (at the lower end: D_K is closest to the least
  /// filtered surface, i.e. to the naive NDF; compare hellinger_naive_kirchhoff).
  bool at_lower_end = false, at_upper_end = false;
  double kirchhoff_raw_integral = 0;
  /// Fraction of D_K's mass beyond the scans' Nyquist band (a spacing above lambda_q / 4),
  /// removed by the mask: near 1, D_K holds only a small band about the pole and the sweep
  /// compares little (KirchhoffAccumulator::aliased_fraction).
  double kirchhoff_aliased_fraction = 0;
  /// The three tables at the sweep resolution (the filtered one at the chosen sigma) and their
  /// pairwise distances.
  TabulatedNdf naive{3}, filtered{3}, kirchhoff{3};
  double hellinger_naive_kirchhoff = 0, hellinger_naive_filtered = 0,
         hellinger_filtered_kirchhoff = 0;
  /// Everything but the tables: {"sigma_m", "hellinger", "curve": [{sigma_m, hellinger}...],
  /// "sweep": {...}, "distances": {...}}.
  nlohmann::json to_json() const;
};

/// Hands every scan of the set, levelled, to the callback, in the same order on every call.
using ScanVisitor = std::function<void(const std::function<void(const Surface&)>&)>;

/// The sweep over the scans of `for_each_scan` (called twice: D_K, the naive NDF and the coarse
/// sweep; then the refinement). Throws InputError when the scan is too small for a sweep (its
/// range would be empty).
FilterSigmaAuto choose_filter_sigma(const ScanVisitor& for_each_scan,
                                    const FilterSigmaAutoOptions& options);
/// Surfaces in memory (already levelled).
FilterSigmaAuto choose_filter_sigma(const std::vector<Surface>& surfaces,
                                    const FilterSigmaAutoOptions& options);
/// Scans read from files and levelled with `leveling`, one in memory at a time, on this rank.
FilterSigmaAuto choose_filter_sigma(const std::vector<std::string>& paths, const ReadOptions& read,
                                    const LevelingSpec& leveling,
                                    const FilterSigmaAutoOptions& options);

/// The curve as CSV ("sigma_m,hellinger" and one line per point, ascending; atomic write).
void write_filter_sigma_curve_csv(const FilterSigmaAuto& result, const std::string& path);

}  // namespace microbrdf
