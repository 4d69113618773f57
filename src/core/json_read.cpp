#include "microbrdf/json_read.hpp"

#include "microbrdf/error.hpp"
#include "microbrdf/file_read.hpp"

namespace microbrdf {

namespace {
// Thrown by the parser callback to stop at the first container past the limit.
struct TooDeep {};
}  // namespace

nlohmann::json parse_json_text(std::string_view text, const std::string& origin,
                               bool ignore_comments) {
  // The callback sees every container as it opens, with the number of containers around it:
  // parsing stops there, before the document grows deeper (nlohmann's parser itself keeps an
  // explicit stack, so the text is never recursed into).
  const nlohmann::json::parser_callback_t limit = [](int depth, nlohmann::json::parse_event_t ev,
                                                     nlohmann::json&) {
    if ((ev == nlohmann::json::parse_event_t::object_start ||
         ev == nlohmann::json::parse_event_t::array_start) &&
        depth >= kMaxJsonDepth)
      throw TooDeep{};
    return true;
  };
  try {
    return nlohmann::json::parse(text.begin(), text.end(), limit, true, ignore_comments);
  } catch (const TooDeep&) {
    throw FileError(origin, "JSON nested deeper than " + std::to_string(kMaxJsonDepth) +
                                " levels (objects and arrays inside one another)");
  } catch (const nlohmann::json::exception& e) {
    throw FileError(origin, std::string("not valid JSON: ") + e.what());
  }
}

nlohmann::json read_json_file(const std::string& path, bool ignore_comments) {
  const auto bytes = read_file_bytes(path, kMaxJsonFileBytes);
  return parse_json_text(
      std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), path,
      ignore_comments);
}

}  // namespace microbrdf
