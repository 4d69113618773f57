// The microbrdf command line with the toy model registered (tests/toy/toy_cli.sh runs it).
#include "commands.hpp"
#include "toy/toy_ndf.hpp"

int main(int argc, char** argv) {
  microbrdf::register_ndf_model(microbrdf::toy::make_toy_model());  // the registration line
  return microbrdf::cli::run_main(argc, argv);
}
