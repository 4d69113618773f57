#include "commands.hpp"
namespace microbrdf::cli {
void register_generate(CLI::App& app) { app.add_subcommand("generate", "(not yet implemented)"); }
}  // namespace microbrdf::cli
