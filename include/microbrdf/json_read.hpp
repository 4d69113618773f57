#pragma once
// Reading JSON that comes from files (scenes, sidecars, file metadata): the nesting depth is
// limited while parsing, so a hostile document can never be deep enough to overflow the stack
// of the recursive copies, comparisons and destructors that JSON values use.
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace microbrdf {

/// Deepest nesting of objects and arrays accepted in any JSON input.
inline constexpr int kMaxJsonDepth = 64;
/// Largest JSON file read (bytes): the document model takes about ten times the text.
inline constexpr std::size_t kMaxJsonFileBytes = 64u << 20;

/// Parses `text`; `origin` names the file in errors. Throws FileError("<origin>: not valid
/// JSON: ...") or FileError("<origin>: JSON nested deeper than 64 levels ...").
nlohmann::json parse_json_text(std::string_view text, const std::string& origin,
                               bool ignore_comments = false);

/// Reads and parses the file at `path` (a regular file of at most kMaxJsonFileBytes).
nlohmann::json read_json_file(const std::string& path, bool ignore_comments = false);

}  // namespace microbrdf
