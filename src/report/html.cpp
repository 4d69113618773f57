#include "report/html.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "core/markup_escape.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/units.hpp"

namespace microbrdf::report {

std::string escape(std::string_view text) { return detail::markup_escape(text); }

std::string base64(const std::vector<std::uint8_t>& b) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((b.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < b.size(); i += 3) {
    const std::uint32_t v = (b[i] << 16) | (b[i + 1] << 8) | b[i + 2];
    out += t[v >> 18];
    out += t[(v >> 12) & 63];
    out += t[(v >> 6) & 63];
    out += t[v & 63];
  }
  if (i + 1 == b.size()) {
    const std::uint32_t v = b[i] << 16;
    out += t[v >> 18];
    out += t[(v >> 12) & 63];
    out += "==";
  } else if (i + 2 == b.size()) {
    const std::uint32_t v = (b[i] << 16) | (b[i + 1] << 8);
    out += t[v >> 18];
    out += t[(v >> 12) & 63];
    out += t[(v >> 6) & 63];
    out += '=';
  }
  return out;
}

std::vector<std::uint8_t> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw FileError::missing(path);
    throw FileError(path, "cannot open");
  }
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::string data_uri(const std::string& path, const std::string& mime) {
  auto bytes = read_bytes(path);
  if (bytes.empty()) throw FileError(path, "empty image");
  return "data:" + mime + ";base64," + base64(bytes);
}

std::string inline_svg(const std::string& path, const std::string& prefix) {
  auto bytes = read_bytes(path);
  std::string s(bytes.begin(), bytes.end());
  const auto start = s.find("<svg");
  if (start == std::string::npos) throw FileError(path, "no <svg> element");
  s = s.substr(start);
  // Prefix ids and the three ways Cairo refers to them.
  const std::pair<std::string, std::string> rules[] = {
      {"id=\"", "id=\"" + prefix}, {"href=\"#", "href=\"#" + prefix}, {"url(#", "url(#" + prefix}};
  for (const auto& [from, to] : rules) {
    std::string out;
    std::size_t pos = 0;
    for (;;) {
      const auto hit = s.find(from, pos);
      if (hit == std::string::npos) break;
      out.append(s, pos, hit - pos);
      out += to;
      pos = hit + from.size();
    }
    out.append(s, pos);
    s = std::move(out);
  }
  return s;
}

std::string num(double v, int digits) {
  if (!std::isfinite(v)) return "— (not defined for this input)";
  if (v == 0) return "0";
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

std::string length(double metres, int digits) {
  if (!std::isfinite(metres)) return "— (not defined for this input)";
  return format_length(metres, digits);
}

std::string degrees(double radians, int digits) {
  return num(radians * 180.0 / M_PI, digits) + " deg";
}

std::string num_or(const nlohmann::json& v, const std::string& missing, int digits) {
  if (!v.is_number()) return missing;
  const double d = v.get<double>();
  return std::isfinite(d) ? num(d, digits) : missing;
}

}  // namespace microbrdf::report
