#pragma once
// Registration of the CLI subcommands. Each cmd_*.cpp defines one register_* function; the
// subcommand's callback runs the work and records the exit code (0 ok, 1 failure, 2 usage).
#include <CLI/CLI.hpp>
#include <functional>

namespace microbrdf::cli {

void register_all(CLI::App& app);
/// The whole command line (what main does): parses, runs the subcommand, returns the exit code.
int run_main(int argc, char** argv);
void register_info(CLI::App& app);
void register_convert(CLI::App& app);
void register_generate(CLI::App& app);
void register_ndf(CLI::App& app);
void register_tabulate(CLI::App& app);
void register_slice(CLI::App& app);
void register_plot(CLI::App& app);
void register_brdf(CLI::App& app);
void register_brdf_sh(CLI::App* brdf);  ///< info, sh-project, sh-estimate under `brdf`
void register_sun(CLI::App& app);
void register_fit(CLI::App& app);
void register_predict(CLI::App& app);
void register_render(CLI::App& app);
void register_texture(CLI::App& app);
void register_simulate(CLI::App& app);
void register_measured(CLI::App& app);
void register_export(CLI::App& app);
void register_export_gltf(CLI::App* export_cmd);  ///< `export gltf`

/// Runs `body`, turning microbrdf errors into "microbrdf <cmd>: error: <message>" on stderr and
/// a non-zero exit code.
void run_guarded(const char* command, const std::function<void()>& body);
int exit_code();
/// Records a failure without an exception (e.g. `info --keep-going` after it went on).
void set_exit_code(int code);

}  // namespace microbrdf::cli
