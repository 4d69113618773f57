#pragma once
// Small pieces for writing the HTML report: escaping, base64 data URIs, inline SVG with unique
// ids, and numbers printed with their units (never "nan" or "inf").
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace microbrdf::report {

/// &, <, >, " escaped.
std::string escape(std::string_view text);
/// RFC 4648 base64.
std::string base64(const std::vector<std::uint8_t>& bytes);
/// Reads a file whole. Throws FileError.
std::vector<std::uint8_t> read_bytes(const std::string& path);
/// "data:<mime>;base64,..." of a file. Throws FileError (also for an empty file).
std::string data_uri(const std::string& path, const std::string& mime);
/// An SVG file's <svg> element with every id (and each reference to it) prefixed by `prefix`,
/// so several Cairo SVGs (which all name their glyphs "glyph0-1", ...) can live in one page.
/// Throws FileError.
std::string inline_svg(const std::string& path, const std::string& prefix);

/// A number with `digits` significant digits ("0.0123", "1.23e+05"); a non-finite value reads
/// "— (not defined for this input)" (the report never shows nan/inf; callers that know why a
/// value is missing say so themselves).
std::string num(double v, int digits = 4);
/// A length with an SI prefix ("110 nm").
std::string length(double metres, int digits = 4);
/// Radians printed in degrees ("12.3 deg").
std::string degrees(double radians, int digits = 4);
/// num() of a JSON number; `missing` when the value is null or not a number.
std::string num_or(const nlohmann::json& v, const std::string& missing, int digits = 4);

}  // namespace microbrdf::report
