// Axis tick placement and labels for plots.
#include "plot/ticks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace microbrdf::detail {

std::string format_tick(double v, double step) {
  if (std::abs(v) < 1e-9 * std::abs(step)) v = 0;  // -1.2e-17 -> 0
  char buf[64];
  const double av = std::abs(v);
  if (v != 0 && (av >= 1e5 || av < 1e-4)) {
    std::snprintf(buf, sizeof buf, "%.6g", v);
  } else {
    // Enough decimals to write the step exactly (0.25 -> 2, 25 -> 0, 0.5 -> 1).
    int dec = 0;
    if (step > 0)
      while (dec < 12) {
        const double scaled = step * std::pow(10.0, dec);
        if (std::abs(scaled - std::round(scaled)) < 1e-6 * scaled) break;
        ++dec;
      }
    std::snprintf(buf, sizeof buf, "%.*f", std::min(dec, 12), v);
  }
  std::string s = buf;
  // "1e-05" -> "1e-5", "1e+06" -> "1e6".
  auto e = s.find('e');
  if (e != std::string::npos) {
    std::string mant = s.substr(0, e), ex = s.substr(e + 1);
    bool neg = !ex.empty() && ex[0] == '-';
    if (!ex.empty() && (ex[0] == '-' || ex[0] == '+')) ex.erase(0, 1);
    while (ex.size() > 1 && ex[0] == '0') ex.erase(0, 1);
    s = mant + "e" + (neg ? "-" : "") + ex;
  }
  return s;
}

std::vector<Tick> linear_ticks(double lo, double hi, int target) {
  std::vector<Tick> out;
  if (!(hi > lo) || !std::isfinite(lo) || !std::isfinite(hi)) return out;
  const double raw = (hi - lo) / std::max(target, 1);
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = 10 * mag;
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0}) {
    if (m * mag >= raw * (1 - 1e-9)) {
      step = m * mag;
      break;
    }
  }
  const double first = std::ceil(lo / step - 1e-9);
  for (double k = first;; k += 1) {
    double v = k * step;
    if (v > hi + 1e-9 * step) break;
    out.push_back({v, format_tick(v, step)});
    if (out.size() > 1000) break;  // cannot happen with a finite range; a guard all the same
  }
  return out;
}

std::vector<Tick> log_ticks(double lo, double hi) {
  std::vector<Tick> out;
  if (!(hi > lo) || !(lo > 0) || !std::isfinite(hi)) return out;
  const double llo = std::log10(lo), lhi = std::log10(hi);
  const int d0 = static_cast<int>(std::floor(llo)), d1 = static_cast<int>(std::ceil(lhi));
  const int ndec = d1 - d0;
  const double span = lhi - llo;
  const int every = ndec > 8 ? (ndec + 5) / 6 : 1;
  const bool minor = ndec <= 8;
  auto inside = [&](double v) {
    double lv = std::log10(v);
    return lv >= llo - 1e-9 && lv <= lhi + 1e-9;
  };
  int labelled = 0;
  for (int d = d0; d <= d1; ++d) {
    const double base = std::pow(10.0, d);
    if (inside(base)) {
      bool lab = (d % every) == 0;
      out.push_back({base, lab ? format_tick(base, base) : std::string()});
      labelled += lab;
    }
    if (!minor) continue;
    for (int m = 2; m <= 9; ++m) {
      double v = m * base;
      if (!inside(v)) continue;
      bool lab = span < 0.5 || (span < 1.2 && (m == 2 || m == 5));
      out.push_back({v, lab ? format_tick(v, base) : std::string()});
      labelled += lab;
    }
  }
  if (labelled < 2) {
    // A narrow range between two 1-2-5 values: label nice linear ticks instead.
    auto lin = linear_ticks(lo, hi, 4);
    out.clear();
    for (auto& t : lin)
      if (t.value > 0) out.push_back(t);
  }
  return out;
}

}  // namespace microbrdf::detail
