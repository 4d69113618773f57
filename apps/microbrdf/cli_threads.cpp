#include "cli_threads.hpp"

#include <cstdio>

#include "microbrdf/threads.hpp"

namespace microbrdf::cli {

int bounded_threads(const char* command, int requested) {
  const int max = max_thread_count();
  if (requested <= max) return requested;
  std::fprintf(stderr, "microbrdf %s: note: --threads %d clamped to %d (%d per core)\n", command,
               requested, max, kThreadsPerCore);
  return max;
}

}  // namespace microbrdf::cli
