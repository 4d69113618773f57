#pragma once
// format_length for messages about absurd values: a length below 1 fm, at or above 1 km, or not
// finite prints as "%g m" ("1e-30 m", "1e+300 m", "inf m"), where format_length would print 0 or
// "n/a" and hide the number the user has to correct.
#include <cmath>
#include <cstdio>
#include <string>

#include "microbrdf/units.hpp"

namespace microbrdf::detail {

inline std::string format_length_any(double metres) {
  const double a = std::fabs(metres);
  if (a >= 1e-15 && a < 1e3) return format_length(metres);
  char buf[48];
  std::snprintf(buf, sizeof buf, "%g m", metres);
  return buf;
}

}  // namespace microbrdf::detail
