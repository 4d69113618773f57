// The work queue behind distribute() (docs/scale.md, "Protocol"). Every rank keeps a pool of
// worker threads; its main thread alone talks to MPI (MPI_THREAD_FUNNELED). Rank 0 hands out
// item numbers, receives results and folds them in item order; other ranks ask for as many items
// as they have threads, and every result they return asks for the next one. Waiting is done by
// sleeping on the pool (1 ms polls of MPI), never by spinning in a blocking MPI call, so ranks
// sharing a machine do not steal each other's cores.
#include "microbrdf/distribute.hpp"

#include <mpi.h>
#include <omp.h>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstring>
#include <deque>
#include <exception>
#include <map>
#include <mutex>
#include <optional>
#include <thread>

#include "microbrdf/error.hpp"

namespace microbrdf {
namespace {

using Clock = std::chrono::steady_clock;

enum Tag : int { kRequest = 711, kAssign, kStop, kHead, kValues, kFail };
enum Status : std::uint8_t { kOk = 0, kFileError, kInputError, kOtherError };

double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// One finished item, or the error it raised.
struct Done {
  std::size_t item = 0;
  int rank = 0;
  double seconds = 0;
  Status status = kOk;
  std::string path, message;  // FileError: path and problem; other errors: message only
  // The exception itself when it was raised in this process: rethrown as it is, so a caller's
  // own exception type (a Python KeyboardInterrupt from a progress callback) survives.
  std::exception_ptr original;
  WorkResult result;
};

// Records the exception in flight into `d` (keeps FileError / InputError apart).
void capture_error(Done& d) {
  d.original = std::current_exception();
  try {
    throw;
  } catch (const FileError& e) {
    d.status = kFileError;
    d.path = e.path();
    d.message = e.problem();
  } catch (const InputError& e) {
    d.status = kInputError;
    d.message = e.what();
  } catch (const std::exception& e) {
    d.status = kOtherError;
    d.message = e.what();
  } catch (...) {
    d.status = kOtherError;
    d.message = "unknown error";
  }
}

[[noreturn]] void rethrow(const Done& d) {
  if (d.original) std::rethrow_exception(d.original);
  if (d.status == kFileError) throw FileError(d.path, d.message);
  if (d.status == kInputError) throw InputError(d.message);
  throw std::runtime_error(d.message);
}

std::string describe(const Done& d) {
  return d.status == kFileError ? d.path + ": " + d.message : d.message;
}

// Worker threads of one rank: item numbers in, Done records out.
class LocalPool {
 public:
  LocalPool(int threads, int inner_threads, const std::function<WorkResult(std::size_t)>& compute)
      : compute_(compute) {
    for (int t = 0; t < threads; ++t)
      threads_.emplace_back([this, inner_threads] {
        // Per-thread OpenMP setting: compute (and Eigen inside it) uses this many threads.
        omp_set_num_threads(inner_threads);
        run();
      });
  }
  ~LocalPool() {
    {
      std::lock_guard<std::mutex> lock(m_);
      closing_ = true;
    }
    cv_in_.notify_all();
    for (auto& t : threads_) t.join();
  }
  void push(std::size_t item) {
    {
      std::lock_guard<std::mutex> lock(m_);
      inbox_.push_back(item);
    }
    cv_in_.notify_one();
  }
  bool pop(Done& d) {
    std::lock_guard<std::mutex> lock(m_);
    if (outbox_.empty()) return false;
    d = std::move(outbox_.front());
    outbox_.pop_front();
    return true;
  }
  // Sleeps until a result is ready or the timeout passes.
  void wait(std::chrono::microseconds timeout) {
    std::unique_lock<std::mutex> lock(m_);
    cv_out_.wait_for(lock, timeout, [this] { return !outbox_.empty(); });
  }

 private:
  void run() {
    for (;;) {
      std::size_t item;
      {
        std::unique_lock<std::mutex> lock(m_);
        cv_in_.wait(lock, [this] { return closing_ || !inbox_.empty(); });
        if (inbox_.empty()) return;
        item = inbox_.front();
        inbox_.pop_front();
      }
      Done d;
      d.item = item;
      const auto t0 = Clock::now();
      try {
        d.result = compute_(item);
      } catch (...) {
        capture_error(d);
      }
      d.seconds = since(t0);
      {
        std::lock_guard<std::mutex> lock(m_);
        outbox_.push_back(std::move(d));
      }
      cv_out_.notify_all();
    }
  }
  const std::function<WorkResult(std::size_t)>& compute_;
  std::mutex m_;
  std::condition_variable cv_in_, cv_out_;
  std::deque<std::size_t> inbox_;
  std::deque<Done> outbox_;
  bool closing_ = false;
  std::vector<std::thread> threads_;
};

// --- messages: a byte header per result, then its doubles (bit for bit) ---

template <class T>
void put(std::vector<char>& b, const T& v) {
  const char* p = reinterpret_cast<const char*>(&v);
  b.insert(b.end(), p, p + sizeof(T));
}
void put_string(std::vector<char>& b, const std::string& s) {
  put<std::uint64_t>(b, s.size());
  b.insert(b.end(), s.begin(), s.end());
}
struct Reader {
  const std::vector<char>& b;
  std::size_t at = 0;
  template <class T>
  T get() {
    if (at + sizeof(T) > b.size()) throw std::runtime_error("distribute: short message");
    T v;
    std::memcpy(&v, b.data() + at, sizeof(T));
    at += sizeof(T);
    return v;
  }
  std::string get_string() {
    const auto n = get<std::uint64_t>();
    if (at + n > b.size()) throw std::runtime_error("distribute: short message");
    std::string s(b.data() + at, n);
    at += n;
    return s;
  }
};

void send_done(const Done& d) {
  std::vector<char> head;
  put<std::uint64_t>(head, d.item);
  put<double>(head, d.seconds);
  put<std::uint8_t>(head, d.status);
  put_string(head, d.path);
  put_string(head, d.status == kOk ? d.result.text : d.message);
  put<std::uint64_t>(head, d.result.values.size());
  MPI_Send(head.data(), static_cast<int>(head.size()), MPI_BYTE, 0, kHead, MPI_COMM_WORLD);
  if (!d.result.values.empty())
    MPI_Send(d.result.values.data(), static_cast<int>(d.result.values.size()), MPI_DOUBLE, 0,
             kValues, MPI_COMM_WORLD);
}

// One message of unknown length from `source` with `tag`: probed for its size, then received.
std::vector<char> receive_bytes(int source, int tag) {
  MPI_Status st;
  MPI_Probe(source, tag, MPI_COMM_WORLD, &st);
  int bytes = 0;
  MPI_Get_count(&st, MPI_BYTE, &bytes);
  std::vector<char> b(static_cast<std::size_t>(bytes));
  MPI_Recv(b.data(), bytes, MPI_BYTE, source, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return b;
}

Done receive_done(int source) {
  const std::vector<char> head = receive_bytes(source, kHead);
  Reader r{head};
  Done d;
  d.rank = source;
  d.item = r.get<std::uint64_t>();
  d.seconds = r.get<double>();
  d.status = static_cast<Status>(r.get<std::uint8_t>());
  d.path = r.get_string();
  (d.status == kOk ? d.result.text : d.message) = r.get_string();
  d.result.values.resize(r.get<std::uint64_t>());
  if (!d.result.values.empty())
    MPI_Recv(d.result.values.data(), static_cast<int>(d.result.values.size()), MPI_DOUBLE, source,
             kValues, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return d;
}

// A command failed on a rank other than 0 outside distribute(): its error, for rank 0 to report.
std::vector<char> failure_message(const Done& d) {
  std::vector<char> b;
  put<std::uint8_t>(b, d.status);
  put_string(b, d.path.substr(0, 1000));  // short: sent eagerly, even if never received
  put_string(b, d.message.substr(0, 2000));
  return b;
}

Done receive_failure(int source) {
  const std::vector<char> b = receive_bytes(source, kFail);
  Reader r{b};
  Done d;
  d.rank = source;
  d.item = static_cast<std::size_t>(-1);  // after every item: an item's own error comes first
  d.status = static_cast<Status>(r.get<std::uint8_t>());
  d.path = r.get_string();
  d.message = r.get_string();
  return d;
}

// Ranks other than 0: ask for work, compute, send results back until told to stop.
void run_worker(int threads, int inner, const std::function<WorkResult(std::size_t)>& compute) {
  LocalPool pool(threads, inner, compute);
  int slots = threads;
  MPI_Send(&slots, 1, MPI_INT, 0, kRequest, MPI_COMM_WORLD);
  for (;;) {
    bool busy = false;
    int flag = 0;
    MPI_Status st;
    MPI_Iprobe(0, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st);
    if (flag) {
      busy = true;
      if (st.MPI_TAG == kStop) {
        MPI_Recv(nullptr, 0, MPI_BYTE, 0, kStop, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        return;  // rank 0 stops a rank only when none of its items is in flight
      }
      std::uint64_t item = 0;
      MPI_Recv(&item, 1, MPI_UINT64_T, 0, kAssign, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      pool.push(item);
    }
    Done d;
    while (pool.pop(d)) {
      busy = true;
      send_done(d);
    }
    if (!busy) pool.wait(std::chrono::milliseconds(1));
  }
}

struct RankState {
  int slots = 0;
  bool checked_in = false;  // asked for work (or reported a failure) in this distribute()
  bool failed = false;      // failed before it could take part
  std::size_t in_flight = 0, items = 0;
  double seconds = 0;
};

}  // namespace

nlohmann::json WorkStats::to_json(const std::string& items_key) const {
  return {{"ranks", ranks},
          {"threads_per_rank", threads_per_rank},
          {items_key, items_per_rank},
          {"seconds_per_rank", seconds_per_rank},
          {"seconds", seconds}};
}

WorkStats distribute(std::size_t n, const std::function<WorkResult(std::size_t)>& compute,
                     const std::function<void(std::size_t, WorkResult&&)>& consume,
                     const DistributeOptions& o) {
  const int threads = std::max(1, o.threads);
  // One item at a time: compute keeps the caller's OpenMP threads; several: one thread each.
  const int inner = threads == 1 ? omp_get_max_threads() : 1;
  const bool mpi = mpi_active() && mpi_size() > 1 && !mpi_solo();
  const int size = mpi ? mpi_size() : 1;
  if (mpi && mpi_rank() != 0) {
    run_worker(threads, inner, compute);
    return WorkStats{};
  }
  const auto t0 = Clock::now();
  std::vector<RankState> ranks(static_cast<std::size_t>(size));
  ranks[0].slots = threads;
  ranks[0].checked_in = true;
  const std::size_t window =
      o.max_pending > 0 ? o.max_pending : 2 * static_cast<std::size_t>(threads * size) + 2;
  std::size_t next = 0, folded = 0;
  std::map<std::size_t, Done> pending;  // results waiting for an earlier item
  std::optional<Done> error;            // the failure of the lowest item seen
  bool stop = false, ended = false;
  Clock::time_point deadline{};
  auto fail = [&](Done&& d) {
    if (!error || d.item < error->item) error = std::move(d);
    if (!stop)
      deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                    std::chrono::duration<double>(o.abort_after_s));
    stop = true;
    pending.clear();
  };
  auto receive = [&](Done&& d) {
    RankState& r = ranks[static_cast<std::size_t>(d.rank)];
    --r.in_flight;
    ++r.items;
    r.seconds += d.seconds;
    if (d.status != kOk)
      fail(std::move(d));
    else if (!stop)
      pending.emplace(d.item, std::move(d));
  };
  auto can_assign = [&] {
    if (stop || ended || next >= n || next - folded >= window) return false;
    if (o.keep_going && !o.keep_going(next)) ended = true;
    return !ended;
  };
  {
    LocalPool pool(threads, inner, compute);
    for (;;) {
      bool busy = false;
      Done d;
      while (pool.pop(d)) {
        busy = true;
        d.rank = 0;
        receive(std::move(d));
      }
      if (mpi) {
        int flag = 0;
        MPI_Status st;
        for (MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st); flag;
             MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st)) {
          busy = true;
          if (st.MPI_TAG == kRequest) {
            int slots = 0;
            MPI_Recv(&slots, 1, MPI_INT, st.MPI_SOURCE, kRequest, MPI_COMM_WORLD,
                     MPI_STATUS_IGNORE);
            auto& r = ranks[static_cast<std::size_t>(st.MPI_SOURCE)];
            r.slots = slots;
            r.checked_in = true;
          } else if (st.MPI_TAG == kFail) {
            // The rank failed before it joined (a file it cannot see): its error ends the run.
            auto& r = ranks[static_cast<std::size_t>(st.MPI_SOURCE)];
            r.checked_in = r.failed = true;
            r.slots = 0;
            fail(receive_failure(st.MPI_SOURCE));
          } else {
            receive(receive_done(st.MPI_SOURCE));
          }
        }
      }
      // Fold in item order: the one order that makes the result independent of the ranks.
      for (auto it = pending.find(folded); !stop && it != pending.end();
           it = pending.find(folded)) {
        Done ready = std::move(it->second);
        pending.erase(it);
        try {
          consume(folded, std::move(ready.result));
        } catch (...) {
          Done e;
          e.item = folded;
          capture_error(e);
          fail(std::move(e));
          break;
        }
        ++folded;
        busy = true;
      }
      for (std::size_t r = 0; r < ranks.size(); ++r)
        while (ranks[r].in_flight < static_cast<std::size_t>(ranks[r].slots) && can_assign()) {
          if (r == 0) {
            pool.push(next);
          } else {
            const std::uint64_t item = next;
            MPI_Send(&item, 1, MPI_UINT64_T, static_cast<int>(r), kAssign, MPI_COMM_WORLD);
          }
          ++ranks[r].in_flight;
          ++next;
          busy = true;
        }
      std::size_t in_flight = 0;
      bool all_in = true;  // every rank joined, or failed: a failure is never missed
      for (const auto& r : ranks) {
        in_flight += r.in_flight;
        all_in = all_in && r.checked_in;
      }
      if (in_flight == 0 && (stop || (folded == next && (ended || next >= n) && all_in))) break;
      if (stop && Clock::now() > deadline)
        mpi_abort("microbrdf: error: " + describe(*error) + " (ranks still busy after " +
                      std::to_string(o.abort_after_s) + " s were ended)",
                  1);
      if (!busy) pool.wait(std::chrono::milliseconds(mpi ? 1 : 50));
    }
  }  // joins the pool
  if (mpi)
    for (int r = 1; r < size; ++r)
      if (!ranks[static_cast<std::size_t>(r)].failed)
        MPI_Send(nullptr, 0, MPI_BYTE, r, kStop, MPI_COMM_WORLD);
  if (error) rethrow(*error);
  WorkStats s;
  s.ranks = size;
  s.threads_per_rank = threads;
  s.items = folded;
  s.seconds = since(t0);
  for (const auto& r : ranks) {
    s.items_per_rank.push_back(r.items);
    s.seconds_per_rank.push_back(r.seconds);
  }
  return s;
}

void mpi_command_failed(const std::exception_ptr& error, const std::string& message, int code) {
  if (!mpi_active() || mpi_size() < 2 || mpi_solo()) return;
  mpi_note_failure(message, code);
  if (mpi_rank() == 0) {
    // Ranks waiting for work from a distribute() rank 0 never reached: stop waiting.
    for (int r = 1; r < mpi_size(); ++r) MPI_Send(nullptr, 0, MPI_BYTE, r, kStop, MPI_COMM_WORLD);
    return;
  }
  Done d;
  try {
    std::rethrow_exception(error);
  } catch (...) {
    capture_error(d);
  }
  // Static: stays valid for a send that has not completed when this returns.
  static std::vector<char> b;
  b = failure_message(d);
  MPI_Request req;
  MPI_Isend(b.data(), static_cast<int>(b.size()), MPI_BYTE, 0, kFail, MPI_COMM_WORLD, &req);
  // Short enough to go out eagerly; rank 0 may have failed itself and never read it.
  for (int k = 0, done = 0; k < 100; ++k) {
    MPI_Test(&req, &done, MPI_STATUS_IGNORE);
    if (done) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  MPI_Request_free(&req);
}

}  // namespace microbrdf
