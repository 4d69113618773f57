#include "microbrdf/json_read.hpp"

#include <vector>

#include "microbrdf/error.hpp"
#include "microbrdf/file_read.hpp"

namespace microbrdf {

namespace {

using nlohmann::json;

// Builds the document from nlohmann's SAX events with the nesting depth counted as containers
// open: the first container past the limit stops the parse, before the document grows deeper.
// (nlohmann's callback parser would also do that, but after each closed object or array it
// scans its parent for discarded children, which is quadratic in the length of a flat array:
// three megabytes of `[{},{},...]` took over a minute.) Every event here costs O(1) amortised.
class DepthLimitedBuilder final : public json::json_sax_t {
 public:
  explicit DepthLimitedBuilder(const std::string& origin) : origin_(origin) {}
  json take() { return std::move(root_); }

  bool null() override { return put(nullptr); }
  bool boolean(bool v) override { return put(v); }
  bool number_integer(number_integer_t v) override { return put(v); }
  bool number_unsigned(number_unsigned_t v) override { return put(v); }
  bool number_float(number_float_t v, const string_t&) override { return put(v); }
  bool string(string_t& v) override { return put(std::move(v)); }
  bool binary(binary_t& v) override { return put(json::binary(v)); }  // not in JSON text
  bool start_object(std::size_t) override { return open(json::value_t::object); }
  bool start_array(std::size_t) override { return open(json::value_t::array); }
  bool end_object() override { return close(); }
  bool end_array() override { return close(); }
  bool key(string_t& k) override {
    // A repeated key keeps the last value, as nlohmann's own parser does.
    slot_ = &(*open_.back())[std::move(k)];
    return true;
  }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception& e) override {
    throw FileError(origin_, std::string("not valid JSON: ") + e.what());
  }

 private:
  // Stores a value where the parser is: the root, the next array element, or the value of the
  // key just read. Returns the stored value (a new container is then opened there).
  template <class V>
  json* place(V&& v) {
    if (open_.empty()) {
      root_ = json(std::forward<V>(v));
      return &root_;
    }
    json& top = *open_.back();
    if (top.is_array()) {
      top.emplace_back(std::forward<V>(v));
      return &top.back();
    }
    *slot_ = json(std::forward<V>(v));
    return slot_;
  }
  template <class V>
  bool put(V&& v) {
    place(std::forward<V>(v));
    return true;
  }
  bool open(json::value_t type) {
    // open_.size() is the number of containers around this one (0 for the root).
    if (open_.size() >= std::size_t(kMaxJsonDepth))
      throw FileError(origin_, "JSON nested deeper than " + std::to_string(kMaxJsonDepth) +
                                   " levels (objects and arrays inside one another)");
    // Only the innermost open container ever grows, so the pointers to the outer ones (held
    // in open_) stay valid while it does.
    open_.push_back(place(json(type)));
    return true;
  }
  bool close() {
    open_.pop_back();
    return true;
  }

  const std::string& origin_;
  json root_;
  std::vector<json*> open_;
  json* slot_ = nullptr;
};

}  // namespace

nlohmann::json parse_json_text(std::string_view text, const std::string& origin,
                               bool ignore_comments) {
  DepthLimitedBuilder builder(origin);
  try {
    // strict: nothing but white space (and comments, when ignored) after the value.
    json::sax_parse(text.begin(), text.end(), &builder, nlohmann::json::input_format_t::json,
                    /*strict=*/true, ignore_comments);
  } catch (const nlohmann::json::exception& e) {
    throw FileError(origin, std::string("not valid JSON: ") + e.what());
  }
  return builder.take();
}

nlohmann::json read_json_file(const std::string& path, bool ignore_comments) {
  const auto bytes = read_file_bytes(path, kMaxJsonFileBytes);
  return parse_json_text(
      std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), path,
      ignore_comments);
}

}  // namespace microbrdf
