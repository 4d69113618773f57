#pragma once
// Pieces every subcommand shares: reading flags (--spacing, --level), JSON printing, progress.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <string>

#include "microbrdf/io.hpp"
#include "microbrdf/level.hpp"
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

/// Reads a surface and levels it as asked; the levelling description is returned.
Surface load_surface(const std::string& path, const ReadFlags& flags, std::string* leveling_report);

/// The `info --json` record of one surface (ARCHITECTURE.md keys, SI units): the library's
/// stats_json(st) plus the file's path, format and metadata.
nlohmann::json stats_json(const std::string& path, const Surface& s, const SurfaceStats& st);

/// Plots are written as .png or .svg: checked before any work, so a typo costs nothing.
/// Throws InputError naming `flag`.
void check_plot_name(const std::string& flag, const std::string& path);

/// Writes text to `path` atomically, or to stdout when path is "-".
void emit_text(const std::string& path, const std::string& text);

/// Prints one JSON object on stdout.
void print_json(const nlohmann::json& j);

/// "[3/10] scan.x3p" style progress on stderr (silent when `quiet`).
void progress(const char* command, std::size_t index, std::size_t total, const std::string& what);

}  // namespace microbrdf::cli
