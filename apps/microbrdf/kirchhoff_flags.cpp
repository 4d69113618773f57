// The D_K flags of `ndf` and `predict` (kirchhoff_flags.hpp).
#include "kirchhoff_flags.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "cli_checks.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/units.hpp"

namespace microbrdf::cli {

void add_kirchhoff_flags(CLI::App* cmd, KirchhoffFlags& f, const std::string& prefix) {
  cmd->add_option("--patch", f.patch,
                  prefix +
                      "tile size (coherence area, Dong App. A), e.g. 70x53um or 140um (square); "
                      "'whole' = one tile per scan")
      ->capture_default_str()
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            if (text == "none" || text == "whole" || text == "0") return {};
            return length_or_pair_in(kMinLength, kMaxLength)(text);
          },
          "WxH, a length or whole", "PATCH"));
  cmd->add_option("--window", f.window,
                  prefix +
                      "apodisation of each tile: hann (default: a hard-edged tile diffracts the "
                      "specular peak into a cross along the table axes, 40-500x the true BRDF "
                      "at 2-5 deg from specular on polished metal) | gauss | none")
      ->capture_default_str()
      ->check(CLI::IsMember({"none", "hann", "gauss"}));
  cmd->add_option("--dk-stack", f.stack,
                  prefix +
                      "lambda_q of the tables: visible (default: a stack over 360 nm .. 6 x 830 nm "
                      "and --wavelength, so that every direction's lambda_q = 2 lambda / |wi + wo| "
                      "is interpolated for any visible lambda) | wavelength (the stack for "
                      "--wavelength only: cheaper, for slices at one wavelength) | single (one "
                      "table at --wavelength for every direction; consumers warn)")
      ->capture_default_str()
      ->check(CLI::IsMember({"visible", "wavelength", "single"}));
  cmd->add_option("--accuracy", f.accuracy,
                  prefix + "tail bound of the fast method (smaller = more terms)")
      ->capture_default_str();
  cmd->add_flag(
      "--keep-aliases", f.keep_aliases,
      prefix + "keep nodes beyond the scan's Nyquist band (|q_x| > pi/dx, |q_y| > pi/dy)");
  cmd->add_option("--dk-integration", f.integration,
                  prefix +
                      "midpoint (one point per sample with central-difference slopes; default: "
                      "20-60x faster, about 1% off on brushed steel, more on steep or coarse "
                      "scans; right for sampled, band-limited data) | exact (the integral over "
                      "each triangle of the "
                      "piecewise-linear surface, in closed form: right for truly faceted surfaces; "
                      "on a sampled "
                      "smooth one its power falls as sinc^4(q d/2))")
      ->capture_default_str();
  cmd->add_option("--dk-supersample", f.supersample,
                  prefix +
                      "node values as averages of S x S sub-nodes (odd S), or auto (S from the "
                      "tile size so that the table resolves the speckle; 1 = point samples)")
      ->capture_default_str();
}

void add_filter_sigma_flags(CLI::App* cmd, std::string& filter_sigma, std::size_t& sweep_resolution,
                            const std::string& prefix) {
  cmd->add_option("--filter-sigma", filter_sigma,
                  prefix +
                      "Gaussian std of the local plane fit, or 'auto': the sigma whose filtered "
                      "NDF is nearest D_K at --wavelength (Hellinger distance over a sweep)")
      ->capture_default_str()
      ->check(length_in(kMinLength, kMaxLength, {"auto"}));
  cmd->add_option("--sweep-resolution", sweep_resolution,
                  "--filter-sigma auto: table size of the sweep (D_K is slow)")
      ->capture_default_str()
      ->check(count_in(17, 8193));
}

KirchhoffOptions kirchhoff_options(const KirchhoffFlags& f, const std::string& wavelength) {
  KirchhoffOptions o;
  o.wavelength_q = parse_length(wavelength);
  if (!(o.wavelength_q > 0)) throw InputError("--wavelength must be > 0");
  if (f.patch == "none" || f.patch == "whole" || f.patch == "0") {
    o.patch_x = o.patch_y = 0;
  } else {
    const LengthPair lp = parse_length_or_pair(f.patch);
    o.patch_x = lp.x;
    o.patch_y = lp.y;
  }
  o.window = parse_kirchhoff_window(f.window);
  o.stack_wavelengths_q = kirchhoff_stack_layers(f.stack, o.wavelength_q);
  o.accuracy = f.accuracy;
  if (!(o.accuracy > 0 && o.accuracy < 1)) throw InputError("--accuracy must be in (0, 1)");
  o.nyquist_mask = !f.keep_aliases;
  o.integration = parse_kirchhoff_integration(f.integration);
  if (f.supersample == "auto") {
    o.supersample = 0;
  } else {
    char* end = nullptr;
    const long v = std::strtol(f.supersample.c_str(), &end, 10);
    if (end == f.supersample.c_str() || *end != 0 || v < 1 || v > 15 || v % 2 == 0)
      throw InputError("--dk-supersample must be auto or an odd number 1..15, not '" +
                       f.supersample + "'");
    o.supersample = static_cast<std::size_t>(v);
  }
  return o;
}

}  // namespace microbrdf::cli
