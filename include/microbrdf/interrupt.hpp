#pragma once
// Interrupts (Ctrl-C, SIGTERM from a job scheduler, SIGHUP) never leave temporaries behind.
//
// Every temporary output (AtomicFile's "<path>.tmp-PID-N", predict's staging folder) is
// registered while it exists. install_interrupt_cleanup() blocks the signals in every thread
// and takes them in one watcher thread, which removes every registered temporary and ends the
// process with 128 + the signal number (130 for SIGINT, 143 for SIGTERM). Handling the signal
// in an ordinary thread (not an async signal handler) lets it take the registry's lock, so a
// commit in progress finishes before the cleanup starts: outputs are never half-renamed.
#include <functional>
#include <string>

namespace microbrdf {

/// Call once at the start of main(), before any thread exists (threads inherit the blocked
/// signal mask). Child processes should call unblock_interrupts_in_child() after fork().
void install_interrupt_cleanup();
/// Restores the default handling of the signals in a freshly forked child process.
void unblock_interrupts_in_child();

/// A temporary file or folder (removed recursively) to delete on interrupt.
void register_temporary(const std::string& path);
void unregister_temporary(const std::string& path);

/// Runs `f` with the interrupt cleanup held off (renames that must all happen, or none).
void without_interrupts(const std::function<void()>& f);

}  // namespace microbrdf
