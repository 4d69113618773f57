#include "rayleigh_rice_flags.hpp"

#include <cmath>
#include <cstdio>

#include "microbrdf/brdf_spec.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/io.hpp"
#include "microbrdf/material_spec.hpp"
#include "microbrdf/psd.hpp"

namespace microbrdf::cli {

void add_rayleigh_rice_flags(CLI::App* c, RayleighRiceFlags& f) {
  c->add_option("--rayleigh-rice", f.scan,
                "First-order Rayleigh-Rice (vector perturbation) BRDF of a smooth metal from this "
                "scan's own 2-D PSD, with the material's complex index (docs/rayleigh_rice.md). "
                "Valid while 4 pi Sq cos(theta) / lambda << 1 (Sq / lambda below ~0.02-0.05) "
                "and the slopes are small (rms slope < ~0.1): polished, lapped, diamond-turned "
                "metals. The specular delta is not in the slice; the JSON gives it and the TIS");
  c->add_option("--polarisation,--polarization", f.polarisation,
                "With --rayleigh-rice: unpolarised (default), s or p (incident; scattered light "
                "summed), ss, sp, ps, pp (in -> out), or mueller (the 16 Mueller elements per "
                "angle as CSV columns m00..m33; m00 is the unpolarised BRDF)")
      ->check(CLI::IsMember(
          {"unpolarised", "unpolarized", "s", "p", "ss", "sp", "ps", "pp", "mueller"}));
  c->add_option("--psd-window", f.psd_window,
                "With --rayleigh-rice: window of the PSD estimate, hann (default: no edge "
                "leakage along the axes) or none (exact for periodic, generated surfaces)")
      ->check(CLI::IsMember({"hann", "none"}));
  c->add_option("--psd-tile", f.psd_tile,
                "With --rayleigh-rice: the Welch tile the PSD is averaged over (50 % overlap): "
                "auto (default: tiles of 32 correlation lengths when the scan holds 3 per axis, "
                "else the whole scan; one periodogram is speckle, each node's spread equal to "
                "its mean), whole, or a side in samples (less noise, coarser frequency step "
                "1/(tile dx)). The JSON's psd.tile_choice says what was used and why")
      ->check([](const std::string& v) -> std::string {
        try {
          check_psd_tile(v);  // the library's own rule, before any scan is read
          return {};
        } catch (const InputError& e) {
          return e.what();
        }
      });
  add_read_flags(c, f.read, "plane");
}

void check_rayleigh_rice_flags(const RayleighRiceFlags& f, const SpecFlags& spec) {
  if (!f.given()) {
    if (!f.polarisation.empty())
      throw InputError(
          "--polarisation: only the Rayleigh-Rice BRDF has one (--rayleigh-rice SCAN)");
    if (f.psd_tile != "auto" || f.psd_window != "hann")
      throw InputError("--psd-window/--psd-tile: only with --rayleigh-rice SCAN");
    return;
  }
  const nlohmann::json keys = spec.keys();
  for (const auto& k : brdf_keys())
    if (keys.contains(k))
      throw InputError("--rayleigh-rice: give one BRDF (also given: " + key_name(k, KeyStyle::Cli) +
                       ")");
  if (!has_material(keys))
    throw InputError(
        "--rayleigh-rice: needs the metal's optical constants (--metal, --n/--k, "
        "--nk-csv, --r0 or --color)");
  if (keys.contains("fresnel"))
    throw InputError("--fresnel: the Rayleigh-Rice BRDF uses the complex index itself");
  Preflight pre;
  pre.input("--rayleigh-rice", f.scan);
  check_spec_files(pre, spec);
  pre.done();
}

RayleighRiceSource rayleigh_rice_from_flags(const RayleighRiceFlags& f, const SpecFlags& spec) {
  const OpticalConstants material = optical_constants(material_spec(spec, std::nullopt));
  RayleighRiceSource out;
  const Surface s = load_surface(f.scan, f.read, &out.leveling);
  const PsdOptions po = psd_options(s, parse_psd_window(f.psd_window), f.psd_tile);
  auto psd =
      std::make_shared<const AreaPsd>(about_file(f.scan, [&] { return areal_psd(s, po, f.scan); }));
  std::fprintf(stderr, "microbrdf brdf slice: %s: PSD: %s\n", f.scan.c_str(),
               psd->tile_why.c_str());
  // The window-weighted mean square far from Sq^2: the scan's edges hold power (form, a defect)
  // the window plays down, or the scan holds too few correlation areas to estimate the PSD.
  const double ratio = psd->sq > 0 ? psd->integral() / (psd->sq * psd->sq) : 1.0;
  if (ratio < 0.8 || ratio > 1.25)
    std::fprintf(stderr,
                 "microbrdf brdf slice: warning: %s: the PSD holds %.3g x Sq^2 (Sq %.4g nm, "
                 "levelling %s): the scan's edges hold power the window plays down (form the "
                 "levelling left, defects), the scan spans too few correlation lengths%s; the "
                 "TIS closed form uses Sq\n",
                 f.scan.c_str(), ratio, psd->sq * 1e9, f.read.level.c_str(),
                 psd->tiles > 1 ? ", or power below the tiles' frequency step (each tile's mean "
                                  "removes it; --psd-tile whole keeps it)"
                                : "");
  const Polarisation pol = f.polarisation.empty() || f.mueller()
                               ? Polarisation::Unpolarised
                               : parse_polarisation(f.polarisation);
  out.brdf = std::make_shared<const RayleighRiceBrdf>(psd, material, pol);
  return out;
}

nlohmann::json rayleigh_rice_json(const RayleighRiceFlags& f, const RayleighRiceSource& s,
                                  double theta_i, double wavelength_m) {
  const AreaPsd& p = s.brdf->psd();
  const double g = 4 * M_PI * p.sq * std::cos(theta_i) / wavelength_m;
  return {{"scan", f.scan},
          {"leveling", s.leveling},
          {"polarisation", f.mueller() ? "mueller" : to_string(s.brdf->polarisation())},
          {"material", s.brdf->material().name},
          {"psd", psd_json(p)},
          {"tis", tis_json(total_integrated_scatter(*s.brdf, wavelength_m, theta_i))},
          {"validity",
           {{"sq_over_wavelength", p.sq / wavelength_m},
            {"rayleigh_factor", g * g},
            {"rms_slope", p.rms_slope()},
            {"smooth", g * g < 0.1 && p.rms_slope() < 0.1}}}};
}

}  // namespace microbrdf::cli
