#pragma once
// Command-line parse errors said the way every other error is ("microbrdf ndf: error: ..."),
// with what the user probably meant: the nearest subcommand or flag to a misspelt one, every
// unknown flag at once, and where the help is. `microbrdf` alone says where to start.
#include <CLI/CLI.hpp>

namespace microbrdf::cli {

/// Prints `e` (after a failed app.parse(argc, argv)) on stderr, on rank 0 only under mpirun;
/// returns the exit code: 0 for --help and --version, 2 (a usage error) for everything else.
int report_parse_error(CLI::App& app, const CLI::ParseError& e, int argc, char** argv);

/// Edit distance (insertions, deletions, substitutions, transpositions of neighbours).
std::size_t edit_distance(const std::string& a, const std::string& b);

}  // namespace microbrdf::cli
