#pragma once
// The Kirchhoff D_K flags of `ndf` and `predict` (and --filter-sigma, which sweeps against D_K),
// defined and parsed once: the tile (coherence area), apodisation, tail bound, Nyquist mask,
// integration rule and node supersampling (docs/kirchhoff.md). --wavelength is registered by
// each command (in predict it is also the wavelength of the BRDF slices).
#include <CLI/CLI.hpp>
#include <cstddef>
#include <string>
#include <vector>

#include "microbrdf/kirchhoff.hpp"

namespace microbrdf::cli {

/// What the user typed for the D_K flags.
struct KirchhoffFlags {
  std::string patch = "70x53um";  ///< tile size, or whole | none | 0 (one tile per scan)
  std::string window = "hann";
  std::string stack = "visible";
  double accuracy = KirchhoffOptions{}.accuracy;
  bool keep_aliases = false;
  std::string integration = "midpoint";
  std::string supersample = "auto";
};

/// --patch, --window, --accuracy, --keep-aliases, --dk-integration, --dk-supersample. `prefix`
/// starts each help line (e.g. "Kirchhoff: ").
void add_kirchhoff_flags(CLI::App* cmd, KirchhoffFlags& f, const std::string& prefix);

/// --filter-sigma (a length, or 'auto': the sigma whose filtered NDF is nearest D_K) and
/// --sweep-resolution (the table size of that sweep), as `ndf` and `predict` take them.
void add_filter_sigma_flags(CLI::App* cmd, std::string& filter_sigma, std::size_t& sweep_resolution,
                            const std::string& prefix);

/// KirchhoffOptions from the flags and the --wavelength text (resolution, direct and progress
/// are the caller's). Throws InputError naming the flag for a bad value.
KirchhoffOptions kirchhoff_options(const KirchhoffFlags& f, const std::string& wavelength);

}  // namespace microbrdf::cli
