// microbrdf: the command line (cli_main.cpp).
#include "commands.hpp"

int main(int argc, char** argv) { return microbrdf::cli::run_main(argc, argv); }
