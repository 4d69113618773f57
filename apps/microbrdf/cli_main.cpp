// The microbrdf command line: one subcommand per file (cmd_*.cpp); this file only wires them
// up. main.cpp calls it (and a program with models of its own registers them first).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <string>

#include "cli_checks.hpp"
#include "cli_parse_errors.hpp"
#include "commands.hpp"
#include "microbrdf/distribute.hpp"
#include "microbrdf/duration.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/file_size_limit.hpp"
#include "microbrdf/interrupt.hpp"
#include "microbrdf/memory_budget.hpp"
#include "microbrdf/mpi_watchdog.hpp"
#include "microbrdf/version.hpp"

namespace microbrdf::cli {

int run_main(int argc, char** argv) {
  // First, before any thread exists (MPI's included): SIGINT / SIGTERM remove temporaries and
  // exit 130 / 143.
  install_interrupt_cleanup();
  // Writes past `ulimit -f` fail with EFBIG and are reported like a full disk, instead of
  // SIGXFSZ ending the process silently with its temporaries left behind.
  install_file_size_limit_handler();
  // MPI only under mpirun (docs/scale.md); finalised when run_main returns.
  MpiSession mpi(argc, argv);
  CLI::App app{
      "microbrdf: predicts how a surface reflects light from its measured microgeometry.\n"
      "Lengths take units (110nm, 1um); angles are degrees unless marked (0.05rad)."};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("microbrdf ") + version());
  app.add_option_function<std::string>(
         "--max-memory",
         [](const std::string& v) {
           try {
             set_memory_budget(parse_byte_size(v));
           } catch (const InputError& e) {
             throw CLI::ValidationError("--max-memory", e.what());
           }
         },
         "Most memory one input may make the tool allocate (e.g. 2G, 512M); default: half the "
         "physical memory, and at most 64x the size of the file (or 256 MiB) for what a file "
         "expands to")
      ->envname("MICROBRDF_MAX_MEMORY")
      ->trigger_on_parse();
  app.add_option_function<std::string>(
         "--mpi-timeout",
         [](const std::string& v) {
           try {
             mpi_set_timeout(parse_duration(v, "--mpi-timeout"));
           } catch (const InputError& e) {
             // CLI11 puts the flag in front itself.
             const std::string what = e.what(), prefix = "--mpi-timeout: ";
             throw CLI::ValidationError(
                 "--mpi-timeout", what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what);
           }
         },
         "Under mpirun: end the run when a rank has not responded for this long (stopped or "
         "hung), naming it (e.g. 10min, 90s; 0 = never; default 30min); busy ranks respond")
      ->envname("MICROBRDF_MPI_TIMEOUT")
      ->trigger_on_parse();
  app.fallthrough();
  cli::register_all(app);
  cli::guard_integer_options(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; every other parse failure (unknown or missing flag, a value
    // a validator refuses, a missing input file) is a usage error: exit code 2, whatever
    // CLI11's own code for it (105, 106, ...).
    return cli::report_parse_error(app, e, argc, argv);
  }
  return cli::exit_code();
}

}  // namespace microbrdf::cli
