#pragma once
// The areal power spectral density (PSD) of a height map, in the conventions of ISO 25178-2 and
// ISO 10110-8 (docs/rayleigh_rice.md, "The PSD of a scan"):
//
//   PSD(fx, fy) = lim |integral h(x, y) exp(-2 pi i (fx x + fy y)) dx dy|^2 / A
//
// with spatial frequencies f = (fx, fy) in cycles/m (not rad/m) and the PSD in m^4, two-sided:
// the integral of PSD over the whole f plane is the mean square height,
//
//   sum over the grid of PSD dfx dfy = Sq^2   (exactly without a window on one tile).
//
// The estimator (areal_psd):
//  - the surface is used as given (level it first: the CLI's readers level with a plane; form
//    that a plane leaves, a bowl, is power at the lowest frequencies: level it with poly2/3);
//  - each tile (the whole scan by default; else tiles of `tile` samples with 50 % overlap,
//    Welch's method) has the window-weighted mean of its valid samples removed, is multiplied by
//    the window (Hann by default: w = sin^2(pi (i + 1/2) / n) per axis; or none), invalid
//    samples set to 0, transformed (FFTW r2c), and its periodogram dx dy |H|^2 / sum_valid w^2
//    (ISO 10110-8's window normalisation);
//  - the tiles' periodograms are averaged with weights sum_valid w^2 (a tile without valid
//    samples is skipped);
//  - so the integral is the window-weighted mean square height: Sq^2 to rounding without a
//    window on one tile, and for a stationary surface Sq^2 in expectation with any window (the
//    generated Gaussian surfaces of the tests: within 1 %). A scan whose power sits at its edges
//    (form left by the levelling, a defect near a corner) gives less with the Hann window: the
//    ratio is recorded (integral_over_sq2 in psd_json) and the commands warn about it. Nothing
//    is rescaled to force Sq^2: that would spread edge power over every frequency;
//  - the zero-frequency bin is 0: the (window-weighted) mean is removed from each tile, and a
//    rough surface scatters nothing into the specular direction through its mean height.
// Invalid samples are excluded, never filled: the mask's own spectrum smooths the estimate
// (a scan with a few % invalid samples loses little). No detrending beyond the mean per tile.

#include <cstddef>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "microbrdf/surface.hpp"

namespace microbrdf {

enum class PsdWindow { None, Hann };
/// "none" | "hann"; InputError otherwise.
PsdWindow parse_psd_window(const std::string& name);
std::string to_string(PsdWindow w);

struct PsdOptions {
  PsdWindow window = PsdWindow::Hann;
  /// Tile side in samples (tiles of min(tile, nx) x min(tile, ny), 50 % overlap); 0 = the whole
  /// scan as one tile (the finest frequency resolution, 1 / (n dx)). default_psd_options picks
  /// it from the scan.
  std::size_t tile = 0;
  /// Why this tile: one sentence with the numbers (copied into AreaPsd and psd_json).
  std::string tile_why;
};

/// The tile a scan's PSD is averaged over when the user names none (docs/rayleigh_rice.md,
/// "Tiles"). One periodogram is an exponentially distributed estimate at every node (its
/// standard deviation equals its mean; its median is ln 2 of it), so a Rayleigh-Rice BRDF from it
/// is speckle. Welch averaging over tiles removes that, at the price of a coarser frequency step
/// 1/L and the window's blur of the halo. Tiles of L = 32 correlation lengths per axis keep that
/// blur below 5 % at the Gaussian halo's 1e-3 level (Hann: exp(45.4 (tau/L)^2) - 1 = 4.5 %) and
/// the step at 1/32 of 1/tau; they are used when the scan holds at least 3 per axis (side
/// >= 2 L with 50 % overlap). Otherwise, or when the correlation length exceeds what the scan
/// shows (NaN), the whole scan is one tile and `why` says that speckle remains.
/// dx, dy: the sample spacing, m; tau_x, tau_y: the 1/e lags of the height ACF along x and y
/// (SurfaceStats), m.
PsdOptions default_psd_options(std::size_t nx, std::size_t ny, double dx, double dy, double tau_x,
                               double tau_y);
/// The same from the surface's own statistics (compute_stats: one FFT of the ACF).
PsdOptions default_psd_options(const Surface& s);
/// The options a user's words ask for: tile "auto" (default_psd_options; with no window the
/// whole scan, whose periodogram is exact for periodic surfaces), "whole" (one tile) or a side in
/// samples (>= 2); InputError otherwise.
PsdOptions psd_options(const Surface& s, PsdWindow window, const std::string& tile);
/// The checks psd_options makes of `tile` alone (before any scan is read): InputError naming
/// what is accepted unless it is "auto", "whole" or an integer side from 2 to 2^20 samples.
void check_psd_tile(const std::string& tile);

/// The 2-D PSD on a centred frequency grid: node (ix, iy) is
///   fx = (ix - nfx/2) dfx,  fy = (iy - nfy/2) dfy   (integer division; cycles/m),
/// row-major value[iy * nfx + ix] in m^4. The grid spans the band the samples resolve
/// (|fx| <= 1/(2 dx), |fy| <= 1/(2 dy)); beyond it the PSD is unknown and at() returns 0.
struct AreaPsd {
  std::size_t nfx = 0, nfy = 0;
  double dfx = 0, dfy = 0;    ///< grid steps, cycles/m (1 / tile width)
  std::vector<double> value;  ///< m^4
  // How it was made (psd_json records these).
  PsdWindow window = PsdWindow::Hann;
  std::size_t tile_nx = 0, tile_ny = 0;  ///< tile size in samples
  std::size_t tiles = 0;                 ///< tiles averaged
  std::string tile_why;                  ///< PsdOptions::tile_why (empty: not recorded)
  double sq = 0;                         ///< rms height of the scan's valid samples, m
  double dx = 0, dy = 0;                 ///< the scan's spacing, m

  double fx(std::size_t ix) const {
    return (static_cast<double>(ix) - static_cast<double>(nfx / 2)) * dfx;
  }
  double fy(std::size_t iy) const {
    return (static_cast<double>(iy) - static_cast<double>(nfy / 2)) * dfy;
  }
  double at_node(std::size_t ix, std::size_t iy) const { return value[iy * nfx + ix]; }
  /// sum PSD dfx dfy, m^2 (the window-weighted mean square height; see the header comment).
  double integral() const;
  /// Bilinear interpolation at (fx, fy) in cycles/m, m^4; 0 outside the grid. The zero-frequency
  /// node (0 in `value`: the mean is removed) enters as zero_frequency_estimate(), so that the
  /// PSD does not dip to 0 within one step of f = 0 (the scan cannot resolve that cell).
  double at(double fx, double fy) const;
  /// The PSD's value at f = 0 as its four nearest nodes give it (their mean), m^4.
  double zero_frequency_estimate() const;
  /// The rms slope the PSD holds, sqrt(sum (2 pi |f|)^2 PSD dfx dfy) (dimensionless; the
  /// slopes of both axes together, i.e. sqrt(Sdq^2) of ISO 25178 from the spectrum).
  double rms_slope() const;
  /// The power within |f| <= f_max (cycles/m): sum of PSD dfx dfy over the nodes inside, m^2.
  double power_within(double f_max) const;
};

/// The PSD of a scan (see the header comment). Throws InputError for a surface without valid
/// samples or with fewer than 2 x 2 samples per tile, FileError (via check_memory, naming
/// `what`) when the work arrays exceed the memory budget.
AreaPsd areal_psd(const Surface& s, const PsdOptions& options = {},
                  const std::string& what = "surface");

/// The azimuthal average of the 2-D PSD in rings of width max(dfx, dfy): f (cycles/m, ring
/// centres, from 0) and the mean of the 2-D PSD's nodes in the ring (m^4; it is still the 2-D
/// PSD, for an isotropic surface PSD(|f|), not a 1-D profile PSD). Rings beyond the smaller
/// Nyquist frequency are left out (they are not full circles).
struct RadialPsd {
  std::vector<double> f;      ///< cycles/m
  std::vector<double> value;  ///< m^4
  std::vector<std::size_t> count;
};
RadialPsd radial_psd(const AreaPsd& psd);

/// The PSD's record in JSON: conventions and units (frequency_unit "cycles/m", psd_unit "m^4",
/// normalisation text), grid (nfx, nfy, dfx_per_m, dfy_per_m, fx_max_per_m, fy_max_per_m),
/// estimator (window, tile_nx, tile_ny, tiles, tile_choice when recorded), sq_m, integral_m2,
/// integral_over_sq2 and rms_slope.
nlohmann::json psd_json(const AreaPsd& psd);

}  // namespace microbrdf
