#pragma once
// Process CPU time and two machine yardsticks for thread-count comparisons of CPU time.
//
// A program's CPU per unit of work with one thread over that with two mixes what the program
// does differently with one thread and what the machine charges differently. These loops have
// no software difference between the two counts (each of `threads` std::threads does its equal
// share of a fixed amount of work, the calling thread waits in join(), as in a work pool), so
// their ratio is the machine's own:
//  - compute_loop: a dependent integer chain in registers, no memory traffic;
//  - PointerChase: a dependent random walk over a buffer larger than the last-level cache (one
//    DRAM access per step, the latency-bound kind of access a BVH traversal makes), all threads
//    walking the same buffer from different starting points.
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <numeric>
#include <string>
#include <thread>
#include <vector>

namespace microbrdf::bench {

// User + system CPU seconds of the whole process (all threads).
inline double process_cpu() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// Busy CPU seconds of the whole machine since boot, all processes (/proc/stat: user, nice,
// system, irq, softirq, steal); -1 where /proc is not available. Its growth over a run less the
// process's own CPU is what other processes took meanwhile: a sharper note of the load than the
// load average, which lags by a minute and counts this process too.
inline double machine_busy_cpu() {
  std::ifstream f("/proc/stat");
  std::string cpu;
  double user = 0, nice = 0, system = 0, idle = 0, iowait = 0, irq = 0, softirq = 0, steal = 0;
  if (!(f >> cpu >> user >> nice >> system >> idle >> iowait >> irq >> softirq >> steal) ||
      cpu != "cpu")
    return -1;
  const long hz = sysconf(_SC_CLK_TCK);
  return (user + nice + system + irq + softirq + steal) / static_cast<double>(hz > 0 ? hz : 100);
}

// Runs body(t, share) on `threads` new threads, t = 0..threads-1, share = total / threads, and
// returns the sum of their results; the caller only waits.
template <class Body>
std::uint64_t run_split(int threads, std::uint64_t total, Body body) {
  std::vector<std::uint64_t> out(static_cast<std::size_t>(threads));
  std::vector<std::thread> pool;
  const std::uint64_t share = total / static_cast<std::uint64_t>(threads);
  for (int t = 0; t < threads; ++t)
    pool.emplace_back([&, t] { out[static_cast<std::size_t>(t)] = body(t, share); });
  for (auto& th : pool) th.join();
  return std::accumulate(out.begin(), out.end(), std::uint64_t{0});
}

// `steps` iterations of a multiply-xorshift chain split over `threads`; returns a checksum.
inline std::uint64_t compute_loop(int threads, std::uint64_t steps) {
  return run_split(threads, steps, [](int t, std::uint64_t n) {
    std::uint64_t x = 0x9E3779B97F4A7C15ull + static_cast<std::uint64_t>(t);
    for (std::uint64_t i = 0; i < n; ++i) {
      x = x * 0xD1342543DE82EF95ull + 1;
      x ^= x >> 29;
    }
    return x;
  });
}

// A single random cycle through `bytes` / 4 slots (Sattolo's algorithm), walked index by index.
class PointerChase {
 public:
  explicit PointerChase(std::size_t bytes, std::uint64_t seed = 12345)
      : next_(std::max<std::size_t>(bytes / sizeof(std::uint32_t), 2)) {
    std::iota(next_.begin(), next_.end(), std::uint32_t{0});
    std::uint64_t s = seed;
    for (std::size_t i = next_.size() - 1; i > 0; --i) {
      s = s * 6364136223846793005ull + 1442695040888963407ull;
      const std::size_t j = static_cast<std::size_t>((s >> 33) % i);  // j < i: one cycle
      std::swap(next_[i], next_[j]);
    }
  }
  std::size_t bytes() const { return next_.size() * sizeof(std::uint32_t); }
  // `steps` dependent loads split over `threads`, thread t starting at slot t * size / threads;
  // returns the sum of the slots reached.
  std::uint64_t run(int threads, std::uint64_t steps) const {
    return run_split(threads, steps, [this, threads](int t, std::uint64_t n) {
      std::uint32_t i = static_cast<std::uint32_t>(next_.size() / threads * t);
      for (std::uint64_t k = 0; k < n; ++k) i = next_[i];
      return std::uint64_t{i};
    });
  }

 private:
  std::vector<std::uint32_t> next_;
};

}  // namespace microbrdf::bench
