#include "commands.hpp"
namespace microbrdf::cli {
void register_info(CLI::App& app) { app.add_subcommand("info", "(not yet implemented)"); }
}  // namespace microbrdf::cli
