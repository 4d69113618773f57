// MPI start-up and shut-down: initialised only under an MPI launcher, so plain runs pay nothing
// (no MPI runtime, no orted) and the same binary serves both (docs/scale.md, "Design"). Also the
// watchdog that ends a run whose rank stopped answering (docs/scale.md, "Stopped ranks").
#include <fcntl.h>
#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "microbrdf/distribute.hpp"
#include "microbrdf/mpi_watchdog.hpp"

namespace microbrdf {
namespace {

bool g_active = false, g_solo = false;
int g_rank = 0, g_size = 1;
int g_stderr = 2;       // this rank's original stderr (ranks > 0 point fd 2 at /dev/null)
int g_failed_code = 0;  // the command failed on this rank (mpi_note_failure)
std::string g_failed_message;

// This rank's original stderr, whatever fd 2 points at now.
void write_stderr(const std::string& line) {
  if (::write(g_stderr, line.data(), line.size()) < 0) {
    // nothing more can be reported
  }
}

// How long a failed rank waits for the others at the end before ending them all. Rank 0 waits
// for items in flight at most DistributeOptions::abort_after_s (10 s) before it reports.
constexpr double kFailedBarrierSeconds = 30;

// --- the watchdog -----------------------------------------------------------------------------
// Every rank runs one more thread that sends a sign of life (an empty message on a communicator
// of its own) to rank 0, and rank 0 one to every other rank, several times per timeout. A rank
// that stops (SIGSTOP, a node that hangs, a process stuck in the kernel) stops sending; when one
// has been silent for the timeout, the rank watching it says which one and ends every rank
// (MPI_Abort), so mpirun never waits for ever. The thread only sleeps and polls: it costs
// nothing measurable, and it sees a rank busy computing as alive (its own thread still beats).

std::atomic<double> g_timeout_s{kDefaultMpiTimeoutSeconds};
std::atomic<bool> g_watch_stop{false};
std::mutex g_watch_mutex;
std::condition_variable g_watch_wake;
std::thread* g_watch = nullptr;  // never destroyed unless joined (exits skip its destructor)
MPI_Comm g_watch_comm = MPI_COMM_NULL;
std::mutex g_command_mutex;
std::string g_command = "microbrdf";  // "microbrdf <command>" once a command runs
constexpr int kBeatTag = 733;
constexpr int kHostChars = 64;

// Who each rank is, for the message: its process id and host.
struct RankId {
  int pid = 0;
  char host[kHostChars] = {};
};
std::vector<RankId> g_ids;

std::string who(int rank) {
  std::string s = "MPI rank " + std::to_string(rank);
  if (rank >= 0 && std::size_t(rank) < g_ids.size())
    s += " (pid " + std::to_string(g_ids[std::size_t(rank)].pid) + " on " +
         std::string(g_ids[std::size_t(rank)].host) + ")";
  return s;
}

std::string format_seconds(double s) {
  char buf[32];
  if (s >= 120 && s == std::floor(s / 60) * 60)
    std::snprintf(buf, sizeof buf, "%.0f min", s / 60);
  else
    std::snprintf(buf, sizeof buf, "%.3g s", s);
  return buf;
}

void watch() {
  using Clock = std::chrono::steady_clock;
  const bool root = g_rank == 0;
  std::vector<Clock::time_point> seen(std::size_t(g_size), Clock::now());
  Clock::time_point sent{};
  for (;;) {
    if (g_watch_stop.load()) return;
    const double timeout = g_timeout_s.load();
    // A sign of life several times per timeout, at most every 10 s, at least every 50 ms.
    const double beat = timeout > 0 ? std::clamp(timeout / 6, 0.05, 10.0) : 10.0;
    int flag = 0;
    MPI_Status st;
    for (MPI_Iprobe(MPI_ANY_SOURCE, kBeatTag, g_watch_comm, &flag, &st); flag;
         MPI_Iprobe(MPI_ANY_SOURCE, kBeatTag, g_watch_comm, &flag, &st)) {
      MPI_Recv(nullptr, 0, MPI_BYTE, st.MPI_SOURCE, kBeatTag, g_watch_comm, MPI_STATUS_IGNORE);
      seen[std::size_t(st.MPI_SOURCE)] = Clock::now();
    }
    const auto now = Clock::now();
    if (std::chrono::duration<double>(now - sent).count() >= beat) {
      for (int r = 0; r < g_size; ++r) {
        if (r == g_rank || (!root && r != 0)) continue;
        MPI_Request req;
        MPI_Isend(nullptr, 0, MPI_BYTE, r, kBeatTag, g_watch_comm, &req);
        MPI_Request_free(&req);  // an empty message: nothing to keep alive
      }
      sent = now;
    }
    if (timeout > 0) {
      // Rank 0 watches every rank; the others watch rank 0. When rank 0 stops, every other rank
      // notices: the later ranks wait a little longer, so usually one message is printed.
      const double grace = root ? 0 : 0.25 * std::min(g_rank - 1, 8);
      for (int r = 0; r < g_size; ++r) {
        if (r == g_rank || (!root && r != 0)) continue;
        const double silent = std::chrono::duration<double>(now - seen[std::size_t(r)]).count();
        if (silent > timeout + grace) {
          std::string command;
          {
            std::lock_guard<std::mutex> lock(g_command_mutex);
            command = g_command;
          }
          write_stderr(command + ": error: --mpi-timeout: " + who(r) + " has not responded for " +
                       format_seconds(timeout) + " (stopped or hung); every rank was ended" +
                       (root ? "" : " (noticed by rank " + std::to_string(g_rank) + ")") + "\n");
          MPI_Abort(MPI_COMM_WORLD, 1);
          std::_Exit(1);
        }
      }
    }
    // Woken at once by stop_watchdog: a run's end does not wait out the pause.
    std::unique_lock<std::mutex> lock(g_watch_mutex);
    g_watch_wake.wait_for(lock, std::chrono::duration<double>(std::min(beat / 2, 0.2)),
                          [] { return g_watch_stop.load(); });
  }
}

void start_watchdog() {
  RankId me;
  me.pid = static_cast<int>(::getpid());
  char host[MPI_MAX_PROCESSOR_NAME] = {};
  int len = 0;
  MPI_Get_processor_name(host, &len);
  std::snprintf(me.host, sizeof me.host, "%s", host);
  g_ids.resize(std::size_t(g_size));
  MPI_Allgather(&me, sizeof me, MPI_BYTE, g_ids.data(), sizeof me, MPI_BYTE, MPI_COMM_WORLD);
  MPI_Comm_dup(MPI_COMM_WORLD, &g_watch_comm);
  g_watch = new std::thread(watch);
}

void stop_watchdog() {
  if (!g_watch) return;
  {
    std::lock_guard<std::mutex> lock(g_watch_mutex);
    g_watch_stop.store(true);
  }
  g_watch_wake.notify_all();
  g_watch->join();
  delete g_watch;
  g_watch = nullptr;
}

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
    if (pause < std::chrono::milliseconds(4)) pause *= 2;
  }
}

}  // namespace

MpiSession::MpiSession(int& argc, char**& argv) {
  if (!launched_by_mpi()) return;
  // Open MPI probes its high-speed point-to-point layers (UCX, PSM, OFI) when a rank starts,
  // about 0.2 s per rank on a machine without such hardware. microbrdf sends a few large
  // messages per scan, for which the ob1 layer (shared memory, TCP and the fabrics its transport
  // modules reach) is as good: it is asked for unless the user chose a layer (OMPI_MCA_pml, or
  // mpirun --mca pml, which sets it).
  ::setenv("OMPI_MCA_pml", "ob1", 0);
  int provided = 0;
  // Only the calling thread exchanges work (worker threads hand results to it); the watchdog's
  // thread sends its signs of life on a communicator of its own, hence MPI_THREAD_MULTIPLE.
  MPI_Init_thread(&argc, &argv, MPI_THREAD_MULTIPLE, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_size);
  g_active = true;
  // An MPI library without thread support runs without the watchdog (as before it existed).
  if (provided >= MPI_THREAD_MULTIPLE && g_size > 1) start_watchdog();
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
  // The watchdog runs on through the barrier: a rank stopped now would otherwise hold it.
  if (!sleeping_barrier(g_failed_code != 0 ? kFailedBarrierSeconds : 0))
    mpi_abort(g_failed_message, g_failed_code);
  stop_watchdog();
  MPI_Finalize();
  g_active = false;
}

bool mpi_active() { return g_active; }
void mpi_set_solo(bool solo) { g_solo = solo; }
bool mpi_solo() { return g_solo; }
int mpi_rank() { return g_rank; }
int mpi_size() { return g_size; }

void mpi_set_timeout(double seconds) { g_timeout_s.store(seconds > 0 ? seconds : 0); }
double mpi_timeout() { return g_timeout_s.load(); }
void mpi_set_command(const std::string& command) {
  std::lock_guard<std::mutex> lock(g_command_mutex);
  g_command = "microbrdf " + command;
}

void mpi_note_failure(const std::string& message, int code) {
  g_failed_code = code != 0 ? code : 1;
  // Rank 0 has printed its message; another rank's is printed only if the run has to be ended
  // (rank 0 then never reported it).
  g_failed_message = g_rank == 0 ? std::string() : message;
}

void mpi_abort(const std::string& message, int code) {
  if (!message.empty()) {
    write_stderr(g_active && g_rank != 0
                     ? "microbrdf (rank " + std::to_string(g_rank) + "): " + message + "\n"
                     : message + "\n");
  }
  if (g_active) MPI_Abort(MPI_COMM_WORLD, code);
  std::_Exit(code);
}

}  // namespace microbrdf
