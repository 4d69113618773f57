#include <cstdio>
#include <exception>

#include "commands.hpp"
#include "microbrdf/error.hpp"

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
  register_measured(app);
  register_export(app);
}

void run_guarded(const char* command, const std::function<void()>& body) {
  try {
    body();
  } catch (const FileError& e) {
    std::fprintf(stderr, "microbrdf %s: error: %s\n", command, e.what());
    g_exit = 1;
  } catch (const InputError& e) {
    std::fprintf(stderr, "microbrdf %s: error: %s\n", command, e.what());
    g_exit = 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "microbrdf %s: internal error: %s\n", command, e.what());
    g_exit = 1;
  }
}

int exit_code() { return g_exit; }

}  // namespace microbrdf::cli
