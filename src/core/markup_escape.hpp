#pragma once
// Escapes & < > " for XML / HTML text and attribute values (SVG titles, report pages, Mitsuba
// scene files), and in attribute mode what an XML attribute needs besides.
#include <string>
#include <string_view>

namespace microbrdf::detail {

/// With `attribute`, also ' as &apos; and tab, newline and carriage return as character
/// references (&#9; &#10; &#13;), which XML attribute-value normalisation would otherwise turn
/// into spaces.
inline std::string markup_escape(std::string_view text, bool attribute = false) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    if (attribute) {
      const char* ref = c == '\''   ? "&apos;"
                        : c == '\t' ? "&#9;"
                        : c == '\n' ? "&#10;"
                        : c == '\r' ? "&#13;"
                                    : nullptr;
      if (ref) {
        out += ref;
        continue;
      }
    }
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
