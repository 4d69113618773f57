// The JSON reader is linear in the size of its input, with the nesting limit kept: flat arrays
// and objects of megabytes parse in well under a second, the documents it builds are the ones
// nlohmann's own parser builds, and nesting past 64 levels is still refused.
#include <gtest/gtest.h>
#include <unistd.h>

#include <ctime>
#include <filesystem>
#include <fstream>
#include <string>

#include "microbrdf/error.hpp"
#include "microbrdf/io.hpp"
#include "microbrdf/json_read.hpp"

using namespace microbrdf;
namespace fs = std::filesystem;

namespace {

// `count` copies of `item` separated by commas, inside `open` ... `close`.
std::string flat(const std::string& open, const std::string& item, std::size_t count,
                 const std::string& close) {
  std::string s = open;
  s.reserve(open.size() + count * (item.size() + 1) + close.size());
  for (std::size_t i = 0; i < count; ++i) {
    if (i) s += ',';
    s += item;
  }
  return s + close;
}

// CPU seconds of this process (the parser is single-threaded): wall time would measure the
// load of the machine the tests share as much as the parser.
double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

double seconds_to_parse(const std::string& text, nlohmann::json* out = nullptr) {
  const double t0 = cpu_seconds();
  nlohmann::json j = parse_json_text(text, "flat.json", true);
  const double s = cpu_seconds() - t0;
  if (out) *out = std::move(j);
  return s;
}

}  // namespace

TEST(JsonLinear, ThreeMegabytesOfEmptyObjectsParseInWellUnderASecond) {
  // 1 million `{}` (3 MB): the callback parser took over a minute on this.
  const std::string text = flat("[", "{}", 1000000, "]");
  ASSERT_GE(text.size(), 3000000u);
  nlohmann::json j;
  const double s = seconds_to_parse(text, &j);
  std::printf("3 MB of [{},{},...]: %.3f s CPU\n", s);
  EXPECT_LT(s, 0.5);
  ASSERT_TRUE(j.is_array());
  EXPECT_EQ(j.size(), 1000000u);
  EXPECT_TRUE(j.front().is_object() && j.front().empty());
  EXPECT_TRUE(j.back().is_object() && j.back().empty());
}

TEST(JsonLinear, OtherFlatShapesAreLinearToo) {
  // Empty arrays in an array, in an object's value, and an object of a quarter million keys.
  const std::string arrays = flat("[", "[]", 1000000, "]");
  const std::string in_object = "{\"dx_m\": 1e-6, \"x\": " + flat("[", "{}", 1000000, "]") + "}";
  std::string keys = "{";
  for (int i = 0; i < 250000; ++i) keys += (i ? ",\"k" : "\"k") + std::to_string(i) + "\":{}";
  keys += "}";
  for (const std::string* t : {&arrays, &in_object, static_cast<const std::string*>(&keys)}) {
    nlohmann::json j;
    const double s = seconds_to_parse(*t, &j);
    std::printf("%zu bytes: %.3f s CPU\n", t->size(), s);
    EXPECT_LT(s, 0.5);
  }
  // Twice the input takes about twice the time, not four times (a loose bound: timing noise).
  const std::string half = flat("[", "{}", 500000, "]"), full = flat("[", "{}", 1000000, "]");
  double t_half = 1e9, t_full = 1e9;
  for (int rep = 0; rep < 3; ++rep) {
    t_half = std::min(t_half, seconds_to_parse(half));
    t_full = std::min(t_full, seconds_to_parse(full));
  }
  EXPECT_LT(t_full, 3.5 * t_half + 0.02) << "half " << t_half << " s, full " << t_full << " s";
}

TEST(JsonLinear, DepthLimitIsKept) {
  const auto nest = [](int depth, const std::string& inner) {
    std::string s;
    for (int i = 0; i < depth; ++i) s += (i % 2) ? "[" : "{\"a\":";
    s += inner;
    for (int i = depth; i-- > 0;) s += (i % 2) ? "]" : "}";
    return s;
  };
  EXPECT_NO_THROW(parse_json_text(nest(kMaxJsonDepth, "1"), "ok.json"));
  // A flat megabyte inside the deepest allowed level is fine; one level more is not.
  EXPECT_NO_THROW(parse_json_text(nest(kMaxJsonDepth - 1, flat("[", "1", 300000, "]")), "ok.json"));
  for (const std::string& deep :
       {nest(kMaxJsonDepth + 1, "1"), nest(kMaxJsonDepth, "[]"), nest(kMaxJsonDepth, "{}"),
        flat("[", "{}", 200000, ",") + nest(kMaxJsonDepth + 1, "1") + "]"}) {
    try {
      parse_json_text(deep, "deep.json");
      FAIL() << "accepted " << deep.substr(0, 80);
    } catch (const FileError& e) {
      EXPECT_EQ(e.path(), "deep.json");
      EXPECT_NE(std::string(e.what()).find("nested deeper than 64 levels"), std::string::npos)
          << e.what();
    }
  }
  // Ten million levels: refused at the 65th, in no time and without growing a stack.
  const std::string million = std::string(10000000, '[') + std::string(10000000, ']');
  const double t0 = cpu_seconds();
  EXPECT_THROW(parse_json_text(million, "deep.json"), FileError);
  EXPECT_LT(cpu_seconds() - t0, 0.5);
}

TEST(JsonLinear, BuildsTheDocumentNlohmannBuilds) {
  // The reference is nlohmann's own DOM parser (no depth limit, no callback).
  const std::string text = R"({"a": [1, -2, 3.5e-7, 18446744073709551615, -9223372036854775808],
    "b": {"c": null, "d": true, "e": false, "f": "\u00e9\"\\\n", "g": [[], {}, [[{"h": 1}]]]},
    "dup": 1, "dup": [2], "": "", "empty": {}, "num": 1e308, "neg0": -0.0})";
  const nlohmann::json mine = parse_json_text(text, "doc.json");
  const nlohmann::json ref = nlohmann::json::parse(text);
  EXPECT_EQ(mine, ref);
  EXPECT_EQ(mine.dump(), ref.dump());
  EXPECT_EQ(mine["dup"], nlohmann::json::array({2}));  // the last of a repeated key
  EXPECT_EQ(parse_json_text("42", "n.json"), nlohmann::json(42));
  EXPECT_EQ(parse_json_text(" \"s\" ", "s.json"), nlohmann::json("s"));
  // Comments are skipped only when asked for; text after the value is an error.
  EXPECT_EQ(parse_json_text("// c\n{\"a\": /* b */ 1}", "c.json", true),
            nlohmann::json({{"a", 1}}));
  EXPECT_THROW(parse_json_text("// c\n{\"a\": 1}", "c.json"), FileError);
  for (const char* bad : {"", "[1,]", "{\"a\" 1}", "[1] [2]", "{\"a\": 1", "\"\xff\"", "[1e999]"}) {
    try {
      parse_json_text(bad, "bad.json");
      ADD_FAILURE() << "accepted " << bad;
    } catch (const FileError& e) {
      EXPECT_EQ(e.path(), "bad.json");
      EXPECT_NE(std::string(e.what()).find("not valid JSON"), std::string::npos) << e.what();
    }
  }
}

TEST(JsonLinear, FlatSidecarOfThreeMegabytesReadsQuickly) {
  // `info` on a height map whose sidecar carries 3 MB of `{}`: read in well under a second.
  const fs::path dir = fs::temp_directory_path() / ("microbrdf-json-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  Surface s(4, 4, 1e-6, 1e-6);
  for (std::size_t i = 0; i < s.z.size(); ++i) s.z[i] = 1e-9 * double(i);
  s.sync_mask();
  write_surface(s, (dir / "h.npy").string());
  {
    std::ofstream f(dir / "h.json");
    f << "{\"dx_m\": 2e-6, \"dy_m\": 3e-6, \"junk\": " << flat("[", "{}", 1000000, "]") << "}";
  }
  const double t0 = cpu_seconds();
  const Surface r = read_surface((dir / "h.npy").string());
  const double secs = cpu_seconds() - t0;
  std::printf("read_surface with a 3 MB sidecar: %.3f s CPU\n", secs);
  EXPECT_LT(secs, 1.0);
  EXPECT_DOUBLE_EQ(r.dx, 2e-6);
  EXPECT_DOUBLE_EQ(r.dy, 3e-6);
  fs::remove_all(dir);
}
