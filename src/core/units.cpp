#include "microbrdf/units.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <string>

#include "microbrdf/error.hpp"

namespace microbrdf {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

// Splits "12.5um" into (12.5, "um"). Throws if there is no leading number.
std::pair<double, std::string_view> split_number(std::string_view text, const char* kind) {
  std::string_view s = trim(text);
  double value = 0;
  auto res = std::from_chars(s.data(), s.data() + s.size(), value);
  if (res.ec != std::errc() || !std::isfinite(value))
    throw InputError("cannot read " + std::string(kind) + " '" + std::string(text) +
                     "': expected a number followed by a unit, e.g. 110nm");
  return {value, trim(std::string_view(res.ptr, s.data() + s.size() - res.ptr))};
}

}  // namespace

double length_unit_to_metres(std::string_view u) {
  u = trim(u);
  struct Unit {
    std::string_view name;
    double scale;
  };
  static constexpr Unit kUnits[] = {
      {"m", 1.0},           {"meter", 1.0},    {"meters", 1.0},       {"metre", 1.0},
      {"metres", 1.0},      {"Meters", 1.0},   {"mm", 1e-3},          {"MilliMeters", 1e-3},
      {"MiliMeters", 1e-3}, {"um", 1e-6},      {"\xC2\xB5m", 1e-6},   {"\xCE\xBCm", 1e-6},
      {"micron", 1e-6},     {"microns", 1e-6}, {"MicroMeters", 1e-6}, {"nm", 1e-9},
      {"NanoMeters", 1e-9}, {"pm", 1e-12},     {"A", 1e-10},          {"cm", 1e-2},
  };
  for (const auto& unit : kUnits)
    if (u == unit.name) return unit.scale;
  return 0.0;
}

double parse_length(std::string_view text) {
  auto [value, unit] = split_number(text, "length");
  if (unit.empty())
    throw InputError("length '" + std::string(text) +
                     "' has no unit; write e.g. 110nm, 1um, 0.5mm or 2e-6m");
  double scale = length_unit_to_metres(unit);
  if (scale == 0)
    throw InputError("unknown length unit '" + std::string(unit) + "' in '" + std::string(text) +
                     "' (use m, mm, um, nm or pm)");
  return value * scale;
}

double parse_angle(std::string_view text) {
  auto [value, unit] = split_number(text, "angle");
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  if (unit.empty() || unit == "deg" || unit == "\xC2\xB0" || unit == "degrees") return value * kDeg;
  if (unit == "rad") return value;
  if (unit == "mrad") return value * 1e-3;
  throw InputError("unknown angle unit '" + std::string(unit) + "' in '" + std::string(text) +
                   "' (use deg, rad or mrad; a bare number means degrees)");
}

LengthPair parse_length_pair(std::string_view text) {
  std::string_view s = trim(text);
  auto x = s.find('x');
  if (x == std::string_view::npos) x = s.find('X');
  if (x == std::string_view::npos)
    throw InputError("cannot read size '" + std::string(text) + "': expected e.g. 70x53um");
  std::string a(trim(s.substr(0, x)));
  std::string b(trim(s.substr(x + 1)));
  // "70x53um": the unit of the second applies to the first too.
  auto [bv, bunit] = split_number(b, "length");
  (void)bv;
  auto [av, aunit] = split_number(a, "length");
  if (aunit.empty()) a = std::to_string(av) + std::string(bunit);
  return {parse_length(a), parse_length(b)};
}

std::string format_length(double metres, int digits) {
  if (!std::isfinite(metres)) return "n/a";
  struct P {
    double scale;
    const char* name;
  };
  static constexpr P kPrefixes[] = {
      {1, "m"}, {1e-3, "mm"}, {1e-6, "um"}, {1e-9, "nm"}, {1e-12, "pm"}};
  // Below a femtometre a length is a rounding residual (e.g. the mean after levelling).
  if (std::fabs(metres) < 1e-15) metres = 0;
  double a = std::fabs(metres);
  const P* chosen = &kPrefixes[0];
  if (a > 0) {
    for (const auto& p : kPrefixes) {
      chosen = &p;
      if (a >= p.scale * 0.9995) break;
    }
  }
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g %s", digits, metres / chosen->scale, chosen->name);
  return buf;
}

LengthPair parse_length_or_pair(std::string_view text) {
  if (text.find_first_of("xX") != std::string_view::npos) return parse_length_pair(text);
  const double d = parse_length(text);
  return {d, d};
}

}  // namespace microbrdf
