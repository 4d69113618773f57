#pragma once
// Internal: a pool of helper threads that sleep between jobs, for passes whose work items are
// independent (filtered normals, the fit's normal equations).

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace microbrdf::detail {

// Helper threads that sleep between jobs. run(n, f) calls f(i) for every i < n on the caller and
// on up to threads - 1 helpers, items taken one at a time from a shared counter. The caller
// never waits for a helper that has not started: a helper woken after the caller took the last
// item finds nothing to do and never touches the job, so on a loaded machine a second thread
// that the scheduler holds back costs nothing (an OpenMP team's join waits for every thread to
// arrive). Concurrent or nested calls run on their caller alone.
class HelperPool {
 public:
  static HelperPool& instance() {
    static HelperPool p;
    return p;
  }
  ~HelperPool() {
    {
      std::lock_guard<std::mutex> lk(m_);
      stop_ = true;
    }
    wake_.notify_all();
    for (auto& t : threads_) t.join();
  }

  void run(std::size_t n, int threads, const std::function<void(std::size_t)>& f) {
    Job job;
    job.n = n;
    job.f = &f;
    std::unique_lock<std::mutex> lk(m_);
    const std::size_t helpers =
        threads > 1 ? std::min<std::size_t>(static_cast<std::size_t>(threads - 1), n - 1) : 0;
    if (job_ || helpers == 0 || n < 2) {
      lk.unlock();
      work(job);
      if (job.error) std::rethrow_exception(job.error);
      return;
    }
    while (threads_.size() < helpers) threads_.emplace_back([this] { helper(); });
    job_ = &job;
    wanted_ = helpers;
    ++generation_;
    lk.unlock();
    wake_.notify_all();
    work(job);
    lk.lock();
    done_.wait(lk, [&] { return job.done.load() == n; });
    job_ = nullptr;  // from here on no helper can pick the job up
    wanted_ = 0;
    done_.wait(lk, [&] { return users_ == 0; });
    lk.unlock();
    if (job.error) std::rethrow_exception(job.error);
  }

 private:
  struct Job {
    std::size_t n = 0;
    const std::function<void(std::size_t)>* f = nullptr;
    std::atomic<std::size_t> next{0}, done{0};
    std::exception_ptr error;
    std::mutex error_mutex;
  };

  void work(Job& j) {
    for (;;) {
      const std::size_t i = j.next.fetch_add(1);
      if (i >= j.n) return;
      try {
        (*j.f)(i);
      } catch (...) {
        std::lock_guard<std::mutex> lk(j.error_mutex);
        if (!j.error) j.error = std::current_exception();
      }
      if (j.done.fetch_add(1) + 1 == j.n) {
        std::lock_guard<std::mutex> lk(m_);
        done_.notify_all();
      }
    }
  }

  void helper() {
    std::uint64_t seen = 0;
    std::unique_lock<std::mutex> lk(m_);
    for (;;) {
      wake_.wait(lk, [&] { return stop_ || (job_ && generation_ != seen && wanted_ > 0); });
      if (stop_) return;
      seen = generation_;
      --wanted_;
      Job* j = job_;
      ++users_;
      lk.unlock();
      work(*j);
      lk.lock();
      if (--users_ == 0) done_.notify_all();
    }
  }

  std::mutex m_;
  std::condition_variable wake_, done_;
  Job* job_ = nullptr;
  std::uint64_t generation_ = 0;
  std::size_t wanted_ = 0;
  int users_ = 0;
  bool stop_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace microbrdf::detail
