#include <cstdio>
#include <exception>

#include "commands.hpp"
#include "microbrdf/distribute.hpp"
#include "microbrdf/error.hpp"

namespace microbrdf::cli {
namespace {
int g_exit = 0;

// Under mpirun these commands spread their work over the ranks (docs/scale.md); every other
// command runs on rank 0 alone while the other ranks wait.
bool distributed(const std::string& command) {
  return command == "ndf" || command == "info" || command == "texture" || command == "simulate" ||
         command == "predict";
}

// The message and exit code of an exception, as every command reports it.
int report(const char* command, std::string* message) {
  char buf[64];
  try {
    throw;
  } catch (const FileError& e) {
    *message = e.what();
    std::snprintf(buf, sizeof buf, "microbrdf %s: error: ", command);
    *message = buf + *message;
    return 1;
  } catch (const InputError& e) {
    std::snprintf(buf, sizeof buf, "microbrdf %s: error: ", command);
    *message = buf + std::string(e.what());
    return 2;
  } catch (const std::exception& e) {
    std::snprintf(buf, sizeof buf, "microbrdf %s: internal error: ", command);
    *message = buf + std::string(e.what());
    return 1;
  }
}
}  // namespace

void register_all(CLI::App& app) {
  register_info(app);
  register_convert(app);
  register_generate(app);
  register_ndf(app);
  register_tabulate(app);
  register_slice(app);
  register_plot(app);
  register_brdf(app);
  register_sun(app);
  register_fit(app);
  register_predict(app);
  register_render(app);
  register_texture(app);
  register_simulate(app);
}

void run_guarded(const char* command, const std::function<void()>& body) {
  if (!mpi_is_root() && !distributed(command)) return;
  try {
    body();
  } catch (...) {
    std::string message;
    const int code = report(command, &message);
    // Errors inside a distributed run reach rank 0 alone; one here on another rank happened
    // outside it (rank 0 may be waiting for this rank): end every rank rather than hang.
    if (!mpi_is_root()) mpi_abort(message, code);
    std::fprintf(stderr, "%s\n", message.c_str());
    g_exit = code;
  }
}

int exit_code() { return g_exit; }

}  // namespace microbrdf::cli
