#include <cstdio>
#include <exception>
#include <new>
#include <stdexcept>

#include "commands.hpp"
#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/memory_budget.hpp"

namespace microbrdf::cli {
namespace {
int g_exit = 0;
}

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
  try {
    OutputGroup outputs;  // every file the command writes: all committed at the end, or none
    body();
    outputs.commit();
  } catch (const FileError& e) {
    std::fprintf(stderr, "microbrdf %s: error: %s\n", command, e.what());
    g_exit = 1;
  } catch (const InputError& e) {
    std::fprintf(stderr, "microbrdf %s: error: %s\n", command, e.what());
    g_exit = 2;
  } catch (const std::bad_alloc&) {
    // Readers check the memory budget before they allocate; this is what is left (a large
    // but legitimate job on a small machine).
    std::fprintf(stderr,
                 "microbrdf %s: error: out of memory (budget %s; --max-memory sets it; try a "
                 "smaller input, resolution or thread count)\n",
                 command, format_bytes(memory_budget()).c_str());
    g_exit = 1;
  } catch (const std::length_error&) {
    std::fprintf(stderr,
                 "microbrdf %s: error: a size beyond what can be allocated was asked for "
                 "(an absurd count or dimension in the input)\n",
                 command);
    g_exit = 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "microbrdf %s: internal error: %s\n", command, e.what());
    g_exit = 1;
  }
}

int exit_code() { return g_exit; }

}  // namespace microbrdf::cli
