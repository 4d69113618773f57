#include "microbrdf/threads.hpp"

#include <omp.h>

#include <algorithm>
#include <thread>

namespace microbrdf {

int max_thread_count() {
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  return std::max(16, kThreadsPerCore * cores);
}

int resolve_thread_count(int requested) {
  if (requested <= 0) return std::clamp(omp_get_max_threads(), 1, max_thread_count());
  return std::min(requested, max_thread_count());
}

}  // namespace microbrdf
