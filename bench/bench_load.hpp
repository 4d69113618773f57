#pragma once
// The machine's 1-minute load average (/proc/loadavg), recorded as a counter next to timings so
// that a figure taken on a busy machine says so; -1 where /proc is not available.
#include <fstream>

namespace microbrdf::bench {

inline double load_average() {
  std::ifstream f("/proc/loadavg");
  double l = -1;
  f >> l;
  return l;
}

}  // namespace microbrdf::bench
