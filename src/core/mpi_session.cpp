// MPI start-up and shut-down: initialised only under an MPI launcher, so plain runs pay nothing
// (no MPI runtime, no orted) and the same binary serves both (docs/scale.md, "Design").
#include <fcntl.h>
#include <mpi.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>

#include "microbrdf/distribute.hpp"

namespace microbrdf {
namespace {

bool g_active = false, g_solo = false;
int g_rank = 0, g_size = 1;
int g_stderr = 2;       // this rank's original stderr (ranks > 0 point fd 2 at /dev/null)
int g_failed_code = 0;  // the command failed on this rank (mpi_note_failure)
std::string g_failed_message;

// How long a failed rank waits for the others at the end before ending them all. Rank 0 waits
// for items in flight at most DistributeOptions::abort_after_s (10 s) before it reports.
constexpr double kFailedBarrierSeconds = 30;

bool launched_by_mpi() {
  return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMIX_RANK") != nullptr;
}

// Waits for every rank without spinning: Open MPI's blocking collectives poll at full speed,
// which would take a core from rank 0 while it writes the outputs. False when `timeout_s` (> 0)
// passed first.
bool sleeping_barrier(double timeout_s = 0) {
  MPI_Request req;
  MPI_Ibarrier(MPI_COMM_WORLD, &req);
  int done = 0;
  auto pause = std::chrono::microseconds(100);
  const auto t0 = std::chrono::steady_clock::now();
  for (;;) {
    MPI_Test(&req, &done, MPI_STATUS_IGNORE);
    if (done) return true;
    if (timeout_s > 0 &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > timeout_s)
      return false;
    std::this_thread::sleep_for(pause);
    if (pause < std::chrono::milliseconds(20)) pause *= 2;
  }
}

}  // namespace

MpiSession::MpiSession(int& argc, char**& argv) {
  if (!launched_by_mpi()) return;
  int provided = 0;
  // Only the calling thread talks to MPI (worker threads hand results to it).
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_size);
  g_active = true;
  if (g_rank != 0) {
    std::fflush(stdout);
    std::fflush(stderr);
    g_stderr = ::dup(2);
    const int null = ::open("/dev/null", O_WRONLY);
    if (null >= 0) {
      ::dup2(null, 1);
      ::dup2(null, 2);
      ::close(null);
    }
  }
}

MpiSession::~MpiSession() {
  if (!g_active) return;
  std::fflush(stdout);
  std::fflush(stderr);
  // After a failure some rank may never arrive (waiting for work that will not come): the
  // error has been reported, so end them all rather than wait for ever.
  if (!sleeping_barrier(g_failed_code != 0 ? kFailedBarrierSeconds : 0))
    mpi_abort(g_failed_message, g_failed_code);
  MPI_Finalize();
  g_active = false;
}

bool mpi_active() { return g_active; }
void mpi_set_solo(bool solo) { g_solo = solo; }
bool mpi_solo() { return g_solo; }
int mpi_rank() { return g_rank; }
int mpi_size() { return g_size; }

void mpi_note_failure(const std::string& message, int code) {
  g_failed_code = code != 0 ? code : 1;
  // Rank 0 has printed its message; another rank's is printed only if the run has to be ended
  // (rank 0 then never reported it).
  g_failed_message = g_rank == 0 ? std::string() : message;
}

void mpi_abort(const std::string& message, int code) {
  if (!message.empty()) {
    std::string line = g_active && g_rank != 0
                           ? "microbrdf (rank " + std::to_string(g_rank) + "): " + message + "\n"
                           : message + "\n";
    if (::write(g_stderr, line.data(), line.size()) < 0) {
      // nothing more can be reported
    }
  }
  if (g_active) MPI_Abort(MPI_COMM_WORLD, code);
  std::_Exit(code);
}

}  // namespace microbrdf
