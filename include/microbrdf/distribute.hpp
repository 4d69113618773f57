#pragma once
// Scale-out: the same program runs alone or under `mpirun` (Open MPI). Work comes as numbered
// items (the scans of a scan set, the blocks of incident directions of a simulation); rank 0
// hands them out from a queue (items differ in cost), every rank computes them on its own worker
// threads, and rank 0 folds the results in item order. Because the fold order is fixed and each
// item's result depends only on the item, the outcome is bit-identical for any number of ranks
// and threads. docs/scale.md has the protocol, the cost model and a cluster how-to.

#include <cstddef>
#include <exception>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace microbrdf {

/// MPI for the lifetime of the program. MPI is initialised only when the process was started by
/// an MPI launcher (mpirun / srun with PMIx: OMPI_COMM_WORLD_SIZE or PMIX_RANK in the
/// environment), so a plain run never starts an MPI runtime. On ranks other than 0, stdout and
/// stderr go to /dev/null (rank 0 speaks for all; a rank that must abort on its own still
/// reports on the original stderr). Construct once in main; the destructor finalises.
class MpiSession {
 public:
  MpiSession(int& argc, char**& argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
};

bool mpi_active();  ///< true when running under an MPI launcher with MPI initialised
int mpi_rank();     ///< 0 when not under MPI
int mpi_size();     ///< 1 when not under MPI
inline bool mpi_is_root() { return mpi_rank() == 0; }
/// Declares that the other ranks take no part in what follows (a command that runs on rank 0
/// alone): distribute() then runs every item on the calling rank instead of waiting for ranks
/// that will never ask for work.
void mpi_set_solo(bool solo);
bool mpi_solo();
/// Ends every rank at once (MPI_Abort) after writing `message` to this rank's original stderr;
/// a plain process exits with `code`. For failures outside a distribute() call that only some
/// ranks see, where waiting for the others would hang.
[[noreturn]] void mpi_abort(const std::string& message, int code);

/// A command that spreads its work over the ranks failed on this rank outside distribute() (a
/// check before the work, a file this rank cannot see). Rank 0 (which prints the error itself):
/// tells every other rank to stop waiting for work. Other ranks: send the error to rank 0
/// instead of printing it; a distribute() on rank 0 then ends with it, so the run reports one
/// error for all ranks. Either way the end of the program waits for the other ranks at most
/// 30 s, then ends every rank (MPI_Abort, with `message` from ranks other than 0). Does nothing
/// in a plain run.
void mpi_command_failed(const std::exception_ptr& error, const std::string& message, int code);
/// Records that this rank failed (mpi_command_failed does it): the final barrier is bounded.
void mpi_note_failure(const std::string& message, int code);

/// What one item produced: bulk numbers (sent bit for bit) and a short text (e.g. JSON counters).
struct WorkResult {
  std::vector<double> values;
  std::string text;
  /// A result computed on rank 0 is consumed there and never sent: a producer may hand the
  /// object itself over here instead of packing it into `values` (no copy of large tables).
  std::shared_ptr<void> local;
};

/// Who did what: items and busy seconds per rank (rank 0 first).
struct WorkStats {
  int ranks = 1;
  int threads_per_rank = 1;
  std::vector<std::size_t> items_per_rank;
  std::vector<double> seconds_per_rank;  ///< seconds spent computing items (summed over threads)
  std::size_t items = 0;                 ///< items computed and folded (all ranks)
  double seconds = 0;                    ///< wall time of the whole distribution
  /// {"ranks": N, items_key: [...], "seconds_per_rank": [...], "threads_per_rank": T}
  nlohmann::json to_json(const std::string& items_key) const;
};

struct DistributeOptions {
  /// Concurrent items per rank, each on its own thread (compute then runs single-threaded for
  /// OpenMP: omp_get_max_threads() is 1 inside). 1 = one item at a time, with the caller's
  /// OpenMP threads available inside compute.
  int threads = 1;
  /// Most results rank 0 holds that cannot be folded yet (an earlier item is still running);
  /// when reached, rank 0 stops handing out items until the gap closes. 0 = 2 x all threads + 2.
  std::size_t max_pending = 0;
  /// Rank 0: asked with the item's number before each item is handed out (in increasing order);
  /// false ends the run early, before that item (time limits).
  std::function<bool(std::size_t)> keep_going;
  /// After an error, how long rank 0 waits for items in flight before ending every rank with
  /// MPI_Abort (seconds).
  double abort_after_s = 10;
};

/// Runs items 0 .. n-1 over all ranks and threads. `compute(i)` may run on any rank and thread
/// (it must depend only on i); `consume(i, result)` runs on rank 0's calling thread, in
/// increasing i. On other ranks distribute() returns after the last item with empty stats.
/// If compute throws on any rank (or consume throws), no new item is handed out, items in
/// flight are drained, every rank returns, and rank 0 rethrows the error of the lowest item
/// (FileError and InputError keep their type and message); other ranks return normally.
WorkStats distribute(std::size_t n, const std::function<WorkResult(std::size_t)>& compute,
                     const std::function<void(std::size_t, WorkResult&&)>& consume,
                     const DistributeOptions& options = {});

}  // namespace microbrdf
