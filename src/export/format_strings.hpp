#pragma once
// Strings written into the scene formats the exports produce, escaped for each (or refused when
// the format cannot hold them), so that a file name with quotes, backslashes, newlines, `&<>`
// or non-ASCII letters reads back as the same name, and never ends a string or a comment early.
#include <string>
#include <string_view>

namespace microbrdf::detail {

/// True when `s` is well-formed UTF-8 (no overlong forms, no surrogates, nothing past U+10FFFF).
bool is_utf8(std::string_view s);

/// A pbrt-v4 string literal, quotes included: `"` and `\` escaped, and newline, carriage return,
/// tab, backspace and form feed as \n \r \t \b \f (the escapes pbrt-v4's tokenizer decodes; a raw
/// newline would end the string with an error). Other bytes, UTF-8 or not, are kept as they are:
/// pbrt reads file names as bytes.
std::string pbrt_string(std::string_view s);

/// A pbrt comment: every line of `s` starts with "# " (a newline in `s` would otherwise end the
/// comment and make the rest of the line a directive). Ends with a newline.
std::string pbrt_comment(std::string_view s);

/// An XML 1.0 attribute value (without the quotes) in a UTF-8 document: & < > " ' as entities,
/// and tab, newline and carriage return as character references (&#9; &#10; &#13;), which
/// attribute-value normalisation would otherwise turn into spaces. Throws FileError(`file`, ...)
/// for what XML 1.0 cannot hold: bytes that are not UTF-8, and control characters below U+0020
/// other than those three.
std::string xml_attribute(std::string_view s, const std::string& file);

/// An XML comment holding `s`: "--" broken up, bytes that are not UTF-8 and the control
/// characters XML cannot hold written as \xNN (a comment is only read by people).
std::string xml_comment(std::string_view s);

}  // namespace microbrdf::detail
