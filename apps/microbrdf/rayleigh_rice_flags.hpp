#pragma once
// `brdf slice --rayleigh-rice SCAN`: the flags of the first-order Rayleigh-Rice BRDF
// (include/microbrdf/rayleigh_rice.hpp) and the one way the commands build it from them.
#include <CLI/CLI.hpp>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_common.hpp"
#include "microbrdf/rayleigh_rice.hpp"
#include "spec_flags.hpp"

namespace microbrdf::cli {

struct RayleighRiceFlags {
  std::string scan;                 ///< --rayleigh-rice (empty: not asked for)
  std::string polarisation;         ///< --polarisation (empty: unpolarised)
  std::string psd_window = "hann";  ///< --psd-window
  std::string psd_tile = "auto";    ///< --psd-tile: auto, whole or a side in samples
  ReadFlags read;                   ///< --spacing, --z-scale, --level for the scan
  bool given() const { return !scan.empty(); }
  bool mueller() const { return polarisation == "mueller"; }
};

/// --rayleigh-rice, --polarisation, --psd-window, --psd-tile and the scan's read flags.
void add_rayleigh_rice_flags(CLI::App* cmd, RayleighRiceFlags& f);

/// Usage errors found before reading anything: another BRDF kind given too, --polarisation or
/// the PSD flags without --rayleigh-rice, no material, a scan that is not there.
void check_rayleigh_rice_flags(const RayleighRiceFlags& f, const SpecFlags& spec);

/// The scan read and levelled, its PSD, and the BRDF with the material of `spec` (Mueller asks
/// for the unpolarised BRDF, whose mueller() gives the matrix).
struct RayleighRiceSource {
  std::shared_ptr<const RayleighRiceBrdf> brdf;
  std::string leveling;  ///< what levelling did
};
RayleighRiceSource rayleigh_rice_from_flags(const RayleighRiceFlags& f, const SpecFlags& spec);

/// The JSON summary's Rayleigh-Rice part: scan, polarisation, psd (psd_json), tis (tis_json at
/// theta_i and the wavelength) and the validity numbers (sigma / lambda, rms slope from the PSD).
nlohmann::json rayleigh_rice_json(const RayleighRiceFlags& f, const RayleighRiceSource& s,
                                  double theta_i, double wavelength_m);

}  // namespace microbrdf::cli
