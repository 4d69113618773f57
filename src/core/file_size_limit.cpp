#include "microbrdf/file_size_limit.hpp"

#include <sys/resource.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>

namespace microbrdf {

namespace {
// Set from the signal handler: a lock-free atomic store is async-signal-safe.
std::atomic<bool> g_reached{false};
static_assert(std::atomic<bool>::is_always_lock_free);

extern "C" void on_sigxfsz(int) { g_reached.store(true, std::memory_order_relaxed); }
}  // namespace

void install_file_size_limit_handler() {
  struct sigaction sa {};
  sa.sa_handler = on_sigxfsz;
  sigemptyset(&sa.sa_mask);
  // No SA_RESTART: the write that crossed the limit must fail with EFBIG, not be retried.
  sa.sa_flags = 0;
  sigaction(SIGXFSZ, &sa, nullptr);
}

bool file_size_limit_reached() { return g_reached.load(std::memory_order_relaxed); }

std::string file_size_limit_problem() {
  std::string limit;
  struct rlimit r {};
  if (getrlimit(RLIMIT_FSIZE, &r) == 0 && r.rlim_cur != RLIM_INFINITY)
    limit = " (ulimit -f: " +
            (r.rlim_cur % 1024 == 0 ? std::to_string(r.rlim_cur / 1024) + " KiB"
                                    : std::to_string(r.rlim_cur) + " bytes") +
            ")";
  return "the file size limit" + limit + " was reached; as on a full disk, no output was written";
}

std::string write_failure_problem(int err) {
  if (err == EFBIG || file_size_limit_reached()) return file_size_limit_problem();
  if (err == ENOSPC) return "the disk is full; no output was written";
  return err != 0 ? std::string("write failed: ") + std::strerror(err)
                  : "write failed (disk full?)";
}

}  // namespace microbrdf
