#pragma once
// Pieces every subcommand shares: reading flags (--spacing, --level), JSON printing, progress.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <string>

#include "microbrdf/io.hpp"
#include "microbrdf/level.hpp"
#include "microbrdf/microfacet.hpp"
#include "microbrdf/statistics.hpp"
#include "microbrdf/surface.hpp"

namespace microbrdf::cli {

struct ReadFlags {
  std::string spacing;  ///< "110nm" or "110x130nm" (dx x dy); empty = from the file
  std::string level;    ///< none|plane|polyN
};

/// Adds --spacing and --level to a subcommand; `default_level` is what measured data get.
void add_read_flags(CLI::App* cmd, ReadFlags& flags, const std::string& default_level);
ReadOptions read_options(const ReadFlags& flags);

/// Scans with fewer valid samples than this fraction get a warning on stderr.
inline constexpr double kSparseValidFraction = 0.1;
/// The warning, naming the file, when `s` is below kSparseValidFraction.
void warn_if_sparse(const std::string& path, const Surface& s);

/// Reads a surface and levels it as asked (a warning when it is sparse, errors naming the
/// file); the levelling description is returned.
Surface load_surface(const std::string& path, const ReadFlags& flags, std::string* leveling_report);

/// The `info --json` record of one surface (ARCHITECTURE.md keys, SI units): the library's
/// stats_json(st) plus the file's path, format and metadata.
nlohmann::json stats_json(const std::string& path, const Surface& s, const SurfaceStats& st);

/// The analytic-model flags shared by `tabulate` and `brdf` (--model, --alpha or
/// --alpha-x/--alpha-y, --phi, --theta-x/y/z; angles with units) as an NdfSpec. --alpha sets
/// both widths; --alpha-y defaults to alpha_x. Throws InputError without a roughness.
struct ModelFlags {
  std::string model = "ggx";
  double alpha = 0, alpha_x = 0, alpha_y = 0;
  std::string phi = "0", theta_x = "0", theta_y = "0", theta_z = "0";
};
NdfSpec ndf_spec(const ModelFlags& f);
/// Registers those flags on a subcommand; returns the --model option.
CLI::Option* add_model_flags(CLI::App* cmd, ModelFlags& f);

/// Prints one JSON object on stdout.
void print_json(const nlohmann::json& j);

/// "[3/10] scan.x3p" style progress on stderr (silent when `quiet`).
void progress(const char* command, std::size_t index, std::size_t total, const std::string& what);

}  // namespace microbrdf::cli
