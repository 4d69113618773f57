// microbrdf command line: one subcommand per file (cmd_*.cpp); this file only wires them up.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>

#include "commands.hpp"
#include "microbrdf/distribute.hpp"

int main(int argc, char** argv) {
  // MPI only under mpirun (docs/scale.md); finalised when main returns.
  microbrdf::MpiSession mpi(argc, argv);
  CLI::App app{
      "microbrdf: predicts how a surface reflects light from its measured microgeometry.\n"
      "Lengths take units (110nm, 1um); angles are degrees unless marked (0.05rad)."};
  app.require_subcommand(1);
  app.set_version_flag("--version", "microbrdf 0.1.0");
  microbrdf::cli::register_all(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; every other parse failure (unknown or missing flag, a value
    // a validator refuses, a missing input file) is a usage error: exit code 2, whatever
    // CLI11's own code for it (105, 106, ...).
    return app.exit(e) == 0 ? 0 : 2;
  }
  return microbrdf::cli::exit_code();
}
