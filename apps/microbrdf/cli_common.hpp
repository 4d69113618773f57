#pragma once
// Pieces every subcommand shares: reading flags (--spacing, --level), JSON printing, progress
// (cli_progress.hpp) and the checks made before any heavy work (cli_checks.hpp).
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_checks.hpp"
#include "cli_progress.hpp"
#include "microbrdf/io.hpp"
#include "microbrdf/level.hpp"
#include "microbrdf/statistics.hpp"
#include "microbrdf/surface.hpp"

namespace microbrdf::cli {

struct ReadFlags {
  std::string spacing;  ///< "110nm" or "110x130nm" (dx x dy); empty = from the file
  std::string level;    ///< none|plane|polyN
  std::string z_scale;  ///< "1nm": the height of one stored unit; empty = the file's unit
};

/// Adds --spacing, --z-scale and --level to a subcommand; `default_level` is what measured data
/// get.
void add_read_flags(CLI::App* cmd, ReadFlags& flags, const std::string& default_level);
ReadOptions read_options(const ReadFlags& flags);

/// Scans with fewer valid samples than this fraction get a warning on stderr.
inline constexpr double kSparseValidFraction = 0.1;
/// The warning, naming the file, when `s` is below kSparseValidFraction.
void warn_if_sparse(const std::string& path, const Surface& s);

/// Height samples over a scan set, from each scan's {"nx", "ny", "valid"} record (ndf_scanset),
/// with the sparse-scan warning as each scan comes.
struct SampleTally {
  std::size_t all = 0, invalid = 0;
  void add(const std::string& path, const nlohmann::json& scan);
  /// "microbrdf CMD: N of M height samples invalid (x%), skipped" on stderr.
  void print(const char* command) const;
};

/// The scans named by files, folders, globs or @manifests (expand_scan_inputs), each checked to
/// exist and be readable: a missing scan is a usage error (exit 2), all of them listed at once,
/// before any file is parsed.
std::vector<std::string> scan_inputs(const std::vector<std::string>& inputs);

/// Reads a surface and levels it as asked (a warning when it is sparse; errors about its data
/// name the file); the levelling description is returned. A file that does not exist is a
/// usage error (InputError); one that cannot be read is a FileError.
Surface load_surface(const std::string& path, const ReadFlags& flags, std::string* leveling_report);

/// Plots are written as .png or .svg: checked before any work, so a typo costs nothing.
/// Throws InputError naming `flag`.
void check_plot_name(const std::string& flag, const std::string& path);

/// Writes text to `path` atomically, or to stdout when path is "-".
void emit_text(const std::string& path, const std::string& text);

/// Prints one JSON object on stdout.
void print_json(const nlohmann::json& j);

/// "[3/10] scan.x3p" style progress on stderr (Progress::item of cli_progress.hpp).
void progress(const char* command, std::size_t index, std::size_t total, const std::string& what);

}  // namespace microbrdf::cli
