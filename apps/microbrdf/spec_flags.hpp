#pragma once
// The material and BRDF flags of every command, defined once: each flag is a key of the
// library's vocabulary (material_spec.hpp, brdf_spec.hpp) with '_' written '-', and the values
// go to the library's one parser as typed.
#include <CLI/CLI.hpp>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "cli_checks.hpp"
#include "microbrdf/brdf_spec.hpp"
#include "microbrdf/material_spec.hpp"

namespace microbrdf::cli {

/// What the user typed for the material / BRDF flags of one command.
struct SpecFlags {
  std::map<std::string, std::string> text;  ///< key -> value as typed ("" = not given)
  std::vector<std::string> kirchhoff;
  bool mirror = false, separable_g = false, isotropic_average = false;
  bool multiple_scattering = false;
  /// The given flags as a JSON object of vocabulary keys (the parsers' input).
  nlohmann::json keys() const;
};

/// --metal, --n, --k, --nk-csv, --r0, --color and --fresnel. `default_note` says in --help what
/// a command uses when no material is given (e.g. "default: Fe").
void add_material_flags(CLI::App* cmd, SpecFlags& f, const std::string& default_note);
/// The analytic NDF flags: --model, --alpha, --alpha-x, --alpha-y, --phi, --theta-x/y/z.
void add_model_flags(CLI::App* cmd, SpecFlags& f);

/// Which BRDF kinds a command takes.
enum BrdfFlagSet : unsigned {
  kFlagModel = 256,             ///< the analytic model (add_model_flags)
  kFlagNdf = 1,                 ///< --ndf
  kFlagKirchhoff = 2,           ///< --kirchhoff (repeatable)
  kFlagSun = 4,                 ///< --sun
  kFlagSh = 8,                  ///< --sh, --l-filter, --filter-width, --isotropic-average
  kFlagTexture = 16,            ///< --texture
  kFlagLambertian = 32,         ///< --lambertian
  kFlagMirror = 64,             ///< --mirror
  kFlagSeparable = 128,         ///< --separable-g
  kFlagAllBrdfs = 511u & ~16u,  ///< every kind a Brdf can be (all but --texture)
};
/// The flags of the BRDF kinds in `set`.
void add_brdf_flags(CLI::App* cmd, SpecFlags& f, unsigned set);

/// The BRDF and material flags of the exporters (`export bsdf|mitsuba|pbrt|gltf`): every BRDF
/// but the ideal mirror (a delta lobe no table or glTF material holds), a parameter texture.
void add_export_source_flags(CLI::App* c, SpecFlags& f);

/// The material the flags name, or `fallback` when none is given (InputError without one).
MaterialSpec material_spec(const SpecFlags& f, const std::optional<MaterialSpec>& fallback);
/// The BRDF the flags name (InputError when none is given and there is no fallback). A
/// material given with a BRDF that takes none (--sh, --lambertian) is an error.
BrdfSpec brdf_spec(const SpecFlags& f, const std::optional<BrdfSpec>& fallback = std::nullopt);
/// The BRDF the flags name (brdf_spec) built with the material of the flags (required for the
/// kinds that take one); the spec goes to `spec_out` when given.
std::shared_ptr<const Brdf> brdf_from_flags(const SpecFlags& f, BrdfSpec* spec_out = nullptr);

/// Warns on stderr ("microbrdf COMMAND: warning: ...") when the --kirchhoff files hold one D_K
/// table in all (one lambda_q for every direction); reads only their sidecars.
void warn_single_dk_table(const SpecFlags& f, const std::string& command);
/// Cheap checks before any heavy work: the metal is known and every file the material / BRDF
/// flags name exists (--nk-csv, --ndf, --kirchhoff, --sh, --texture); problems go to `pre`.
void check_spec_files(Preflight& pre, const SpecFlags& f);
/// The analytic NDF of the model flags (InputError without a roughness).
NdfSpec ndf_spec(const SpecFlags& f);

}  // namespace microbrdf::cli
