#pragma once
// Synthetic surfaces with known statistics, reproducible from a seed (same seed, same build ->
// same heights). All lengths in metres, angles in radians.

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "microbrdf/surface.hpp"

namespace microbrdf {

/// Gaussian random surface with autocorrelation sigma^2 exp(-(u/tau_x)^2 - (v/tau_y)^2), where
/// u is along `angle` (from the x axis) and v across it. Made by filtering white noise in the
/// Fourier domain with the square root of the Gaussian PSD (periodic), then shifted and scaled
/// so the realisation has mean 0 and rms exactly sigma. Isotropic when tau_y == tau_x.
///
/// Two kinds of noise:
///  - exact_spectrum = true (default): every Fourier coefficient of the noise gets modulus 1 and
///    a random phase, so each realisation's periodogram IS the target PSD and its (circular)
///    ACF is exactly the target: tau and rms slopes come out right on every realisation, even
///    when tau is a sizeable fraction of the grid. Heights are Gaussian by the central limit
///    theorem (a sum of many random-phase cosines).
///  - exact_spectrum = false: complex Gaussian white noise, a true Gaussian process. Sample
///    statistics then scatter between realisations (at tau = 50 samples on 1024^2, tau and rms
///    slope scatter by ~10%), as with a real measurement.
struct GaussianSurfaceParams {
  std::size_t nx = 1024, ny = 1024;
  double dx = 110e-9, dy = 110e-9;  ///< sample spacing, m
  double sigma = 0.1e-6;            ///< rms height, m
  double tau_x = 2e-6;              ///< correlation length along the first axis, m
  double tau_y = 2e-6;              ///< correlation length along the second axis, m
  double angle = 0;                 ///< first axis from the x axis, rad
  std::uint64_t seed = 1;
  bool exact_spectrum = true;
};
Surface generate_gaussian(const GaussianSurfaceParams& p);

/// Sun 2002 section 4: independent 1-D Gaussian profiles by a moving average of white noise
/// with weights exp(-2 x^2 / tau^2) (truncated at 3 tau), which gives the autocorrelation
/// sigma^2 exp(-x^2/tau^2). Each profile is one row (ny = rows). sigma is the process value
/// (not renormalised per realisation, so the sample statistics fluctuate as Sun's did).
struct ProfileParams {
  std::size_t n = 65536;
  std::size_t rows = 1;
  double dx = 0.01e-6;    ///< sample spacing, m
  double sigma = 0.1e-6;  ///< rms height, m
  double tau = 1e-6;      ///< correlation length, m
  std::uint64_t seed = 1;
};
Surface generate_profiles(const ProfileParams& p);

/// Brushed metal: an anisotropic Gaussian base (long correlation along the brushing
/// direction, short across) plus random scratches: grooves with Gaussian cross-section running
/// along the brushing direction over the whole length. Optionally the whole height field is
/// multiplied by a slowly varying log-normal amplitude a(x, y) = exp(m h - c), h a unit Gaussian
/// field with correlation lengths modulation_along / modulation_across, c such that mean a^2 = 1
/// exactly (so the rms slope is kept): the depth of the brushing varies from place to place, as
/// on real brushed metals (Dong 2015 Fig. 11). The NDF is then a scale mixture of Gaussian lobes,
/// heavier-tailed than Beckmann (docs/fitting.md), and small texels differ in roughness.
struct BrushedParams {
  std::size_t nx = 2048, ny = 1024;
  double dx = 110e-9, dy = 110e-9;  ///< sample spacing, m
  double angle = 0;                 ///< brushing direction from the x axis, rad
  double sigma = 0.2e-6;            ///< rms height of the base, m
  double tau_along = 50e-6;         ///< base correlation length along the brushing, m
  double tau_across = 2e-6;         ///< base correlation length across, m
  double scratch_density = 0;       ///< scratches per metre across the brushing
  double scratch_depth = 0;         ///< mean depth (exponentially distributed), m
  double scratch_width = 0;         ///< mean Gaussian sigma of the cross-section, m
  std::uint64_t seed = 1;
  bool exact_spectrum = true;    ///< for the base, see GaussianSurfaceParams
  double modulation = 0;         ///< log-amplitude rms m of the depth modulation (0 = none)
  double modulation_along = 0;   ///< its correlation length along the brushing, m
  double modulation_across = 0;  ///< its correlation length across, m
};
Surface generate_brushed(const BrushedParams& p);

/// A named brushed preset: "stainless4" or "aluminium4" (Dong 2015 Fig. 12). A Gaussian base,
/// scratches and a log-normal depth modulation (so the filtered NDF has heavier-than-Beckmann
/// tails and small texels differ); the ellipsoid fit of the Gaussian-filtered (1 um, Dong section
/// 5.1) NDF has widths about 0.007 along / 0.14 across (stainless #4) or 0.02 / 0.47
/// (aluminium #4), Dong's ellipsoid column. The base is solved (solve_brushed_base) for rms
/// widths 1.6x along and 1.8x across those, the calibrated ratio of the mixture's rms width to its
/// fitted width (docs/fitting.md). Throws InputError for an unknown name.
BrushedParams brushed_preset(const std::string& name);
/// Ratio of the base's rms slope width to the ellipsoid width fitted to the filtered NDF (1 um
/// filter), {along, across}. (1, 1) without depth modulation (a Gaussian base: the fit recovers
/// its rms width); with the presets' log-normal modulation (0.6, 50 um x 8 um) the NDF is a scale
/// mixture whose fitted peak is narrower than its rms width: {1.6, 1.8}, calibrated on 2048 x 1024
/// surfaces, seeds 1-3 (docs/fitting.md). brushed_preset() and `generate brushed --alpha-*` use it.
std::pair<double, double> brushed_modulation_calibration(const BrushedParams& p);
std::vector<std::string> brushed_preset_names();

/// Base parameters that give the filtered widths alpha_along, alpha_across for a Gaussian
/// filter of standard deviation `filter_sigma`, keeping tau_across fixed. Uses
/// <b_u^2> = tau_u tau_v sigma^2 / (8 a_u^{3/2} a_v^{1/2}), a = s^2 + tau^2/4 (docs/theory.md §3.4,
/// anisotropic form). Throws InputError when no solution exists.
void solve_brushed_base(BrushedParams& p, double alpha_along, double alpha_across,
                        double filter_sigma);

/// Predicted Gaussian-filtered Beckmann width along the u axis of an anisotropic Gaussian
/// surface (filter_sigma = 0 gives the unfiltered 2 sigma / tau_u).
double predicted_filtered_alpha(double sigma, double tau_u, double tau_v, double filter_sigma);

/// Parallel cylinders (or grooves cut into a plane when `grooves`): axes along `angle`, spaced
/// `pitch` apart, each axis shifted by a uniform random amount in [-jitter, jitter] * pitch.
struct CylindersParams {
  std::size_t nx = 1024, ny = 1024;
  double dx = 110e-9, dy = 110e-9;
  double radius = 5e-6;
  double pitch = 12e-6;
  double angle = 0;
  double jitter = 0;
  bool grooves = false;
  std::uint64_t seed = 1;
};
Surface generate_cylinders(const CylindersParams& p);

/// Sinusoidal grating z = A sin(2 pi u / P), u = x cos(angle) + y sin(angle).
struct GratingParams {
  std::size_t nx = 1024, ny = 1024;
  double dx = 110e-9, dy = 110e-9;
  double amplitude = 0.1e-6;
  double period = 5e-6;
  double angle = 0;
};
Surface generate_grating(const GratingParams& p);

}  // namespace microbrdf
