// Durations on the command line (--time, --mpi-timeout): a number and a unit, seconds inside.
#include "microbrdf/duration.hpp"

#include <cmath>
#include <string>

#include "microbrdf/error.hpp"

namespace microbrdf {

double parse_duration(std::string_view text, std::string_view flag) {
  const std::string t(text), f(flag);
  const std::string why = f + ": expected e.g. 60s, 2min or 1h (got '" + t + "')";
  std::size_t pos = 0;
  double v = 0;
  try {
    v = std::stod(t, &pos);
  } catch (const std::exception&) {
    throw InputError(why);
  }
  std::string unit = t.substr(pos);
  while (!unit.empty() && unit.front() == ' ') unit.erase(0, 1);
  double scale = 0;
  if (unit.empty() || unit == "s")
    scale = 1;
  else if (unit == "ms")
    scale = 1e-3;
  else if (unit == "min" || unit == "m")
    scale = 60;
  else if (unit == "h")
    scale = 3600;
  else
    throw InputError(f + ": unknown unit '" + unit + "' (ms, s, min or h)");
  // A year at most: beyond that a number is a typo, and an infinite wait is no limit at all.
  if (!std::isfinite(v) || v < 0 || v * scale > 365.0 * 86400) throw InputError(why);
  return v * scale;
}

}  // namespace microbrdf
