#pragma once
// Surface statistics the papers rely on: height moments (Sq = sigma), rms slopes, and the
// correlation length tau of the height autocorrelation C(r) = sigma^2 exp(-r^2/tau^2)
// (Sun 2002 section 3.1; Dong 2015 section 4). Everything mask-aware: invalid samples are
// excluded, never filled.

#include <cstddef>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "microbrdf/surface.hpp"

namespace microbrdf {

struct SurfaceStats {
  std::size_t nx = 0, ny = 0;
  double dx = 0, dy = 0;  ///< m
  std::size_t valid_count = 0;
  double valid_fraction = 0;
  double mean = 0;          ///< m
  double min = 0, max = 0;  ///< m (valid samples)
  double sq = 0;            ///< rms height about the mean (population), m
  double sa = 0;            ///< mean absolute height about the mean, m
  double skewness = 0;      ///< Ssk (0 for Gaussian)
  double kurtosis = 0;      ///< Sku, not excess (3 for Gaussian)
  /// rms slope dz/dx and dz/dy by central differences over samples whose two neighbours are
  /// valid (dimensionless). For C(r) = sigma^2 exp(-r^2/tau^2) the continuum value is
  /// sqrt(2) sigma / tau; central differences read sigma^2 (1 - exp(-4 d^2/tau^2)) / (2 d^2).
  double slope_rms_x = 0, slope_rms_y = 0;
  std::size_t slope_samples_x = 0, slope_samples_y = 0;
  /// Lag at which the normalised ACF first falls to 1/e along x, along y, and radially
  /// (annular average), m; this is tau in exp(-r^2/tau^2). NaN if it never falls that far
  /// within the scan (correlation longer than the scan can show).
  double corr_length_x = 0, corr_length_y = 0, corr_length = 0;
};

/// Normalised autocorrelation on a lag grid: value(lx, ly) for lx in [-(nx-1), nx-1],
/// ly in [-(ny-1), ny-1], stored row-major with (0, 0) at index (ny-1)*(2nx-1) + (nx-1).
/// Mask-aware: C(l) = sum h(p) h(p+l) V V / sum V(p) V(p+l), h = z - mean; lags with fewer than
/// `min_overlap` sample pairs are NaN. value(0,0) = 1.
struct Autocorrelation {
  std::size_t nx = 0, ny = 0;  ///< the surface's size; the lag grid is (2nx-1) x (2ny-1)
  double dx = 0, dy = 0;
  std::vector<double> value;
  double at(long lx, long ly) const {
    return value[static_cast<std::size_t>(ly + static_cast<long>(ny) - 1) * (2 * nx - 1) +
                 static_cast<std::size_t>(lx + static_cast<long>(nx) - 1)];
  }
};

/// ACF by zero-padded FFTs (O(N log N)).
Autocorrelation autocorrelation(const Surface& s, std::size_t min_overlap = 64);

/// Brute-force ACF at a single lag (reference for tests and benchmarks), same definition.
double autocorrelation_direct(const Surface& s, long lx, long ly);

/// Radially averaged profile of a lag-grid quantity: r (m) and mean value in annuli of width
/// min(dx, dy).
struct RadialProfile {
  std::vector<double> r;
  std::vector<double> value;
};
RadialProfile radial_average(const Autocorrelation& acf);

/// First crossing of 1/e, linearly interpolated (m); NaN if none.
double correlation_length(const std::vector<double>& r, const std::vector<double>& acf);

/// Radially averaged power spectral density, convention S(k) = integral C(r) e^{-i k.r} d^2r,
/// so that integral S d^2k / (2 pi)^2 = Sq^2. k in rad/m, S in m^4. Mean removed, invalid
/// samples zero with the normalisation corrected for the valid fraction; no window.
struct Psd {
  std::vector<double> k;  ///< rad/m
  std::vector<double> s;  ///< m^4
};
Psd power_spectrum(const Surface& s);

/// All of SurfaceStats in one pass plus one ACF.
SurfaceStats compute_stats(const Surface& s);

/// The statistics as a JSON object in SI units, the one layout every report uses: nx, ny,
/// dx_m, dy_m, valid_count, valid_fraction, mean_m, min_m, max_m, sq_m, sa_m, skewness,
/// kurtosis, slope_rms_x, slope_rms_y, corr_length_x_m, corr_length_y_m, corr_length_m.
/// A correlation length the scan cannot show (NaN) is null, in memory as in the written file.
nlohmann::json stats_json(const SurfaceStats& st);
/// The `info --json` record of one surface (docs/architecture.md keys, SI units): stats_json(st)
/// plus path, format, invalid_count, leveling, z0_m, instrument, date and z_unit_in_file.
nlohmann::json stats_json(const std::string& path, const Surface& s, const SurfaceStats& st);

}  // namespace microbrdf
