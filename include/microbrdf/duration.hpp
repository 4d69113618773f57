#pragma once
// Durations on the command line (--time, --mpi-timeout): a number and a unit, seconds inside.
#include <string_view>

namespace microbrdf {

/// Parses a duration: "30s", "10min" (or "10m"), "2h", "500ms"; a bare number means seconds.
/// Returns seconds, finite, >= 0 and at most a year. Throws InputError naming `flag`
/// ("--time: expected e.g. 60s, 2min or 1h (got 'soon')").
double parse_duration(std::string_view text, std::string_view flag);

}  // namespace microbrdf
