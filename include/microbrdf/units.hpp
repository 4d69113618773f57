#pragma once
// Parsing and printing quantities with units. Inside microbrdf everything is SI (metres,
// radians); the command line accepts and prints units.

#include <string>
#include <string_view>

namespace microbrdf {

/// Parses a length such as "110nm", "1um", "1µm", "0.5 mm", "2e-6m". A bare number is an
/// error (a length without a unit is ambiguous). Returns metres. Throws InputError.
double parse_length(std::string_view text);

/// Parses an angle: "30deg", "30°", "0.05rad", "0.05 mrad"; a bare number means degrees.
/// Returns radians. Throws InputError.
double parse_angle(std::string_view text);

/// Parses "70x53um" or "70um x 53um" into two lengths in metres. Throws InputError.
struct LengthPair {
  double x = 0, y = 0;
};
LengthPair parse_length_pair(std::string_view text);
/// A pair as above, or one length for both ("110nm" -> 110 nm x 110 nm). Throws InputError.
LengthPair parse_length_or_pair(std::string_view text);

/// Formats a length in metres with an SI prefix that keeps 1 <= |mantissa| < 1000,
/// e.g. 1.1e-7 -> "110 nm". `digits` significant digits. NaN or infinite prints as "n/a".
std::string format_length(double metres, int digits = 4);

/// Unit conversion factor to metres for a unit name as found in instrument files
/// ("m", "mm", "um", "µm", "nm", "pm", "Meters", "MicroMeters", ...). Returns 0 if unknown.
double length_unit_to_metres(std::string_view unit);

}  // namespace microbrdf
