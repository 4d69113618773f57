#pragma once
// Thread counts from the command line: 0 means every core; more than kThreadsPerCore threads
// per core gain nothing and, in the tens of thousands, exhaust the OpenMP runtime.

namespace microbrdf {

inline constexpr int kThreadsPerCore = 8;

/// The most threads a run uses: kThreadsPerCore x the cores (at least 16).
int max_thread_count();

/// `requested` <= 0: every core (OpenMP's default); otherwise at most max_thread_count().
int resolve_thread_count(int requested);

}  // namespace microbrdf
