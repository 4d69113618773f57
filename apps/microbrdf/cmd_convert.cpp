#include "commands.hpp"
namespace microbrdf::cli {
void register_convert(CLI::App& app) { app.add_subcommand("convert", "(not yet implemented)"); }
}  // namespace microbrdf::cli
