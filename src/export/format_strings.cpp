#include "export/format_strings.hpp"

#include <fmt/format.h>

#include <cstdint>

#include "core/markup_escape.hpp"
#include "microbrdf/error.hpp"

namespace microbrdf::detail {
namespace {

// Length of the well-formed UTF-8 sequence at s[i], or 0 when the bytes there are not one.
std::size_t utf8_length(std::string_view s, std::size_t i) {
  const auto b = [&](std::size_t k) { return static_cast<unsigned char>(s[i + k]); };
  const unsigned char c = b(0);
  std::size_t n;
  std::uint32_t cp;
  if (c < 0x80) return 1;
  if (c >= 0xC2 && c <= 0xDF) {
    n = 2;
    cp = c & 0x1F;
  } else if (c >= 0xE0 && c <= 0xEF) {
    n = 3;
    cp = c & 0x0F;
  } else if (c >= 0xF0 && c <= 0xF4) {
    n = 4;
    cp = c & 0x07;
  } else {
    return 0;  // a continuation byte, an overlong lead (C0, C1) or F5..FF
  }
  if (i + n > s.size()) return 0;
  for (std::size_t k = 1; k < n; ++k) {
    if ((b(k) & 0xC0) != 0x80) return 0;
    cp = (cp << 6) | (b(k) & 0x3F);
  }
  const std::uint32_t min = n == 2 ? 0x80 : n == 3 ? 0x800 : 0x10000;
  if (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return 0;
  return n;
}

// Control characters XML 1.0 does not allow anywhere, not even as character references.
bool xml_forbidden(unsigned char c) { return c < 0x20 && c != '\t' && c != '\n' && c != '\r'; }

}  // namespace

bool is_utf8(std::string_view s) {
  for (std::size_t i = 0; i < s.size();) {
    const std::size_t n = utf8_length(s, i);
    if (n == 0) return false;
    i += n;
  }
  return true;
}

std::string pbrt_string(std::string_view s) {
  std::string out = "\"";
  for (char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      case '\t':
        out += "\\t";
        break;
      case '\b':
        out += "\\b";
        break;
      case '\f':
        out += "\\f";
        break;
      default:
        out += c;
    }
  }
  return out + "\"";
}

std::string pbrt_comment(std::string_view s) {
  std::string out = "# ";
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '\r' || s[i] == '\n') {
      if (s[i] == '\r' && i + 1 < s.size() && s[i + 1] == '\n') ++i;
      out += "\n# ";
    } else {
      out += s[i];
    }
  }
  return out + "\n";
}

std::string xml_attribute(std::string_view s, const std::string& file) {
  if (!is_utf8(s))
    throw FileError(file,
                    "the name holds bytes that are not UTF-8, which a Mitsuba XML file cannot "
                    "hold; rename the file");
  for (char c : s)
    if (xml_forbidden(static_cast<unsigned char>(c)))
      throw FileError(file, fmt::format("the name holds the control character 0x{:02X}, which "
                                        "XML cannot hold; rename the file",
                                        static_cast<unsigned char>(c)));
  return markup_escape(s, /*attribute=*/true);
}

std::string xml_comment(std::string_view s) {
  std::string text;
  for (std::size_t i = 0; i < s.size();) {
    const std::size_t n = utf8_length(s, i);
    const auto c = static_cast<unsigned char>(s[i]);
    if (n == 0 || (n == 1 && xml_forbidden(c))) {
      text += fmt::format("\\x{:02X}", c);
      ++i;
    } else {
      text.append(s.substr(i, n));
      i += n;
    }
  }
  // "--" may not appear in a comment, nor may it end with "-" (it would make "--->").
  for (std::size_t p; (p = text.find("--")) != std::string::npos;) text.replace(p, 2, "- -");
  return "<!-- " + text + " -->";
}

}  // namespace microbrdf::detail
