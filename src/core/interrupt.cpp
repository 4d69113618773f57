#include "microbrdf/interrupt.hpp"

#include <pthread.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <mutex>
#include <set>
#include <thread>

#include "microbrdf/distribute.hpp"

namespace microbrdf {

namespace {

std::recursive_mutex& registry_mutex() {
  static std::recursive_mutex m;
  return m;
}

std::set<std::string>& registry() {
  static std::set<std::string> r;
  return r;
}

// The signals to take: those not ignored (nohup ignores SIGHUP, a non-interactive shell SIGINT
// for background jobs; that choice of the caller is kept).
sigset_t interrupt_signals() {
  sigset_t s;
  sigemptyset(&s);
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction old {};
    if (sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
    sigaddset(&s, sig);
  }
  return s;
}

[[noreturn]] void watch(sigset_t signals) {
  int sig = 0;
  while (sigwait(&signals, &sig) != 0) {
  }
  {
    std::lock_guard lock(registry_mutex());  // waits for a commit in progress
    for (const auto& p : registry()) {
      std::error_code ec;
      std::filesystem::remove_all(p, ec);
    }
  }
  // Said once per run: under mpirun every rank gets the signal, and rank 0 alone speaks.
  if (mpi_rank() == 0) {
    const char* name = sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "SIGHUP";
    const std::string m = std::string("microbrdf: interrupted (") + name +
                          "); no output written, temporaries removed\n";
    (void)!::write(STDERR_FILENO, m.data(), m.size());
  }
  ::_exit(128 + sig);
}

}  // namespace

void install_interrupt_cleanup() {
  static std::once_flag once;
  std::call_once(once, [] {
    const sigset_t s = interrupt_signals();
    pthread_sigmask(SIG_BLOCK, &s, nullptr);
    std::thread(watch, s).detach();
  });
}

void unblock_interrupts_in_child() {
  const sigset_t s = interrupt_signals();
  pthread_sigmask(SIG_UNBLOCK, &s, nullptr);
}

void register_temporary(const std::string& path) {
  std::lock_guard lock(registry_mutex());
  registry().insert(path);
}

void unregister_temporary(const std::string& path) {
  std::lock_guard lock(registry_mutex());
  registry().erase(path);
}

void without_interrupts(const std::function<void()>& f) {
  std::lock_guard lock(registry_mutex());
  f();
}

}  // namespace microbrdf
