#pragma once
// Escapes & < > " for XML / HTML text and attribute values (SVG titles, report pages, Mitsuba
// scene files).
#include <string>
#include <string_view>

namespace microbrdf::detail {

inline std::string markup_escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

}  // namespace microbrdf::detail
