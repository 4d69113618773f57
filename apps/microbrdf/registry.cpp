#include <cstdio>
#include <exception>
#include <new>
#include <stdexcept>

#include "commands.hpp"
#include "microbrdf/atomic_file.hpp"
#include "microbrdf/distribute.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/file_size_limit.hpp"
#include "microbrdf/memory_budget.hpp"
#include "microbrdf/mpi_watchdog.hpp"
#include "microbrdf/run_inputs.hpp"

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
    // After a write went past the file-size limit, every later failure is that one (the
    // writer's own message says at best "write failed").
    *message = file_size_limit_reached() ? e.path() + ": " + file_size_limit_problem() : e.what();
    std::snprintf(buf, sizeof buf, "microbrdf %s: error: ", command);
    *message = buf + *message;
    // An input file that is not there is a usage error (2), like a wrong flag: the user named
    // it. A file that exists but cannot be read or parsed, or an output that cannot be written
    // (disk full, no permission), is a failure while working (1).
    return e.is_missing() ? 2 : 1;
  } catch (const InputError& e) {
    std::snprintf(buf, sizeof buf, "microbrdf %s: error: ", command);
    *message = buf + std::string(e.what());
    return 2;
  } catch (const OutOfMemory& e) {
    std::snprintf(buf, sizeof buf, "microbrdf %s: error: ", command);
    *message = buf + std::string(e.what());
    return 1;
  } catch (const std::bad_alloc&) {
    // Readers check the memory budget before they allocate; this is what is left (a large
    // but legitimate job on a small machine).
    std::snprintf(buf, sizeof buf, "microbrdf %s: error: ", command);
    *message = buf + std::string("out of memory (budget ") + format_bytes(memory_budget()) +
               "; --max-memory sets it; try a smaller input, resolution or thread count)";
    return 1;
  } catch (const std::length_error&) {
    std::snprintf(buf, sizeof buf, "microbrdf %s: error: ", command);
    *message = buf + std::string(
                         "a size beyond what can be allocated was asked for (an absurd count or "
                         "dimension in the input)");
    return 1;
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
  register_measured(app);
  register_export(app);
  register_export_gltf(app.get_subcommand("export"));  // its own file: cmd_export_gltf.cpp
}

void run_guarded(const char* command, const std::function<void()>& body) {
  mpi_set_command(command);  // the watchdog's message names it
  if (!distributed(command)) {
    if (!mpi_is_root()) return;
    mpi_set_solo(true);  // library calls that could spread work keep it on this rank
  }
  try {
    const RunInputs inputs;  // every file read: no output of the command may replace one
    OutputGroup outputs;     // every file the command writes: all committed at the end, or none
    body();
    outputs.commit();
  } catch (...) {
    std::string message;
    const int code = report(command, &message);
    // Errors inside a distributed run reach rank 0 alone; one here on another rank happened
    // outside it (a check every rank makes, a file this rank cannot see): rank 0 reports it,
    // once for all ranks (docs/scale.md, "Errors"). A plain run only prints.
    mpi_command_failed(std::current_exception(), message, code);
    if (mpi_is_root()) std::fprintf(stderr, "%s\n", message.c_str());
    g_exit = code;
  }
}

int exit_code() { return g_exit; }

void set_exit_code(int code) { g_exit = code; }

}  // namespace microbrdf::cli
