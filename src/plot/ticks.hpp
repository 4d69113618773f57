#pragma once
// Axis ticks for plot.cpp (internal; tested in tests/test_plot.cpp).
#include <string>
#include <vector>

namespace microbrdf::detail {

struct Tick {
  double value = 0;   ///< data value
  std::string label;  ///< empty for a minor tick
};

/// "Nice" linear ticks (steps 1, 2, 2.5 or 5 x 10^k) covering [lo, hi], about `target` of them.
std::vector<Tick> linear_ticks(double lo, double hi, int target = 6);

/// Log ticks for [lo, hi] (both > 0): labelled decades (every k-th decade when there are many)
/// with minor ticks at 2..9; when the range spans less than about one decade, 2 and 5 (or all
/// of 1..9) are labelled too.
std::vector<Tick> log_ticks(double lo, double hi);

/// Tick label: shortest of %g-style forms, "1e-05" written as "1e-5".
std::string format_tick(double v, double step);

}  // namespace microbrdf::detail
