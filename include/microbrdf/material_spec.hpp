#pragma once
// The one material vocabulary: what a metal (or any reflector) is made of, as the command line,
// the scene JSON and the Python module name it, and the one factory that turns it into a Fresnel
// term.
//
// Keys (CLI flag = "--" + key with '_' -> '-'; JSON key and Python keyword = key):
//   metal    built-in optical constants by name (metal_names(): Au Ag Cu Al Fe ...)
//   n, k     a constant complex refractive index n + i k (dimensionless; both or neither)
//   nk_csv   a CSV file "wavelength_nm,n,k" of optical constants
//   r0       a normal-incidence reflectance in [0, 1) (eta = 1, kappa from R0: Sun 2002 5.2)
//   color    an sRGB colour "r,g,b" (0..1, or 0..255 when a value exceeds 1) or "#rrggbb": a
//            smooth reflectance spectrum of that colour, eta = 1
//   fresnel  exact (complex-index Fresnel equations, the default) or schlick (Schlick's
//            approximation from the normal-incidence reflectance spectrum)
// At most one of metal / n,k / nk_csv / r0 / color. Values may be JSON strings or numbers.
// Two more forms exist for micro-scenes and analytic studies, never as command-line flags:
// "perfect" (R = 1 at every angle) and a dielectric of relative index "eta".

#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "microbrdf/fresnel.hpp"

namespace microbrdf {

/// How parse errors name a key: "--nk-csv" (cli), "\"nk_csv\"" (json) or "nk_csv=" (python).
enum class KeyStyle { Cli, Json, Python };
/// The key as the user typed it in that style.
std::string key_name(const std::string& key, KeyStyle style);

/// A value of the vocabulary as a number: a JSON number, or a string holding one as typed on a
/// command line ("1.2"). Throws InputError naming the key otherwise.
double spec_number(const nlohmann::json& v, const std::string& key, KeyStyle style);
/// A value of the vocabulary that must be a JSON string. Throws InputError naming the key.
std::string spec_text(const nlohmann::json& v, const std::string& key, KeyStyle style);

/// exact: the Fresnel equations with the complex index; schlick: R0 + (1 - R0)(1 - cos)^5.
enum class FresnelMode { Exact, Schlick };

struct MaterialSpec {
  enum class Form { Metal, Nk, NkCsv, R0, Color, Perfect, Dielectric };
  Form form = Form::Metal;
  std::string metal = "Fe";  ///< form metal: a name metal() accepts
  double n = 0, k = 0;       ///< form nk: n > 0, k >= 0 (dimensionless)
  std::string nk_csv;        ///< form nk_csv: path of the CSV file
  double r0 = 0;             ///< form r0: normal-incidence reflectance in [0, 1)
  std::string color;         ///< form color: as typed ("0.9,0.7,0.4", "#e6c27a")
  double eta = 1.5;          ///< form dielectric: relative refractive index (> 0)
  FresnelMode fresnel = FresnelMode::Exact;

  /// A built-in metal (the default form).
  static MaterialSpec named_metal(const std::string& name);
  /// One line for reports, e.g. "metal Cu, exact Fresnel".
  std::string describe() const;
  /// The spec in the vocabulary above (parse_material(to_json()) gives it back).
  nlohmann::json to_json() const;
};

/// The material keys, in the order --help lists them.
const std::vector<std::string>& material_keys();
/// True when `keys` (a JSON object) holds any material key other than "fresnel".
bool has_material(const nlohmann::json& keys);

/// Reads the material keys of a JSON object (other keys are ignored: the caller checks its own).
/// Values: strings (as typed on a command line: "1.2", "Cu") or numbers. With no material key the
/// result is `fallback`, or InputError ("give a material: ...") when there is none. Throws
/// InputError naming the key (in `style`) for two forms at once, a value of the wrong type, an
/// unknown metal, n without k, r0 outside [0, 1) or a colour that does not parse.
MaterialSpec parse_material(const nlohmann::json& keys,
                            const std::optional<MaterialSpec>& fallback = std::nullopt,
                            KeyStyle style = KeyStyle::Json);

/// The optical constants of the spec (metal table, constant index, CSV, from R0 or from the
/// colour). Throws InputError for the forms that have none (perfect, dielectric) and FileError
/// for an unreadable CSV.
OpticalConstants optical_constants(const MaterialSpec& spec);

/// The Fresnel term: ConductorFresnel (exact) or SchlickFresnel of the normal-incidence
/// reflectance spectrum (schlick); PerfectMirrorFresnel for perfect, DielectricFresnel for a
/// dielectric. Throws InputError / FileError as optical_constants() does.
std::shared_ptr<const Fresnel> make_fresnel(const MaterialSpec& spec);

}  // namespace microbrdf
