// The limits that keep hostile input harmless: JSON depth, the memory budget and its messages,
// all-or-nothing output groups, interrupt registration, data errors that name their file.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/io.hpp"
#include "microbrdf/json_read.hpp"
#include "microbrdf/memory_budget.hpp"
#include "microbrdf/microscene.hpp"
#include "microbrdf/threads.hpp"

using namespace microbrdf;
namespace fs = std::filesystem;

namespace {

std::string nested(int depth) {
  return std::string(static_cast<std::size_t>(depth), '[') +
         std::string(static_cast<std::size_t>(depth), ']');
}

fs::path scratch() {
  const fs::path d =
      fs::temp_directory_path() / ("microbrdf-hostile-" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

TEST(JsonDepth, LimitHoldsExactlyAtSixtyFour) {
  EXPECT_NO_THROW(parse_json_text(nested(kMaxJsonDepth), "ok.json"));
  try {
    parse_json_text(nested(kMaxJsonDepth + 1), "deep.json");
    FAIL() << "65 levels accepted";
  } catch (const FileError& e) {
    EXPECT_EQ(e.path(), "deep.json");
    EXPECT_NE(std::string(e.what()).find("nested deeper than 64"), std::string::npos);
  }
  // Objects count as levels too, and a million levels are refused as quickly as 65.
  std::string deep;
  for (int i = 0; i < 1000000; ++i) deep += "{\"a\":";
  deep += "1" + std::string(1000000, '}');
  EXPECT_THROW(parse_json_text(deep, "million.json"), FileError);
}

TEST(JsonDepth, SyntaxErrorsNameTheFile) {
  try {
    parse_json_text("{\"a\": ", "cut.json");
    FAIL();
  } catch (const FileError& e) {
    EXPECT_EQ(e.path(), "cut.json");
    EXPECT_NE(std::string(e.what()).find("not valid JSON"), std::string::npos);
  }
}

TEST(MemoryBudget, ParsesSizes) {
  EXPECT_EQ(parse_byte_size("512M"), 512ull << 20);
  EXPECT_EQ(parse_byte_size("2G"), 2ull << 30);
  EXPECT_EQ(parse_byte_size("1.5GiB"), 3ull << 29);
  EXPECT_EQ(parse_byte_size("1000"), 1000u);
  EXPECT_THROW(parse_byte_size("lots"), InputError);
  EXPECT_THROW(parse_byte_size("-1G"), InputError);
  EXPECT_THROW(parse_byte_size("5X"), InputError);
  EXPECT_EQ(mul_sat(1ull << 40, 1ull << 40), UINT64_MAX);
}

TEST(MemoryBudget, ExpansionRuleNamesFileAndBytes) {
  // The default budget: a 1 MiB file may expand to 256 MiB (the floor), not 300 MiB.
  ASSERT_FALSE(memory_budget_is_explicit());
  EXPECT_NO_THROW(check_expansion("a.x3p", 1u << 20, 256ull << 20, "data"));
  try {
    check_expansion("a.x3p", 1u << 20, 300ull << 20, "a height map");
    FAIL() << "300 MiB from a 1 MiB file accepted";
  } catch (const FileError& e) {
    EXPECT_EQ(e.path(), "a.x3p");
    EXPECT_NE(std::string(e.what()).find("asks for 300 MiB for a height map"), std::string::npos)
        << e.what();
  }
  // 64 x its size for larger files.
  EXPECT_NO_THROW(check_expansion("b.x3p", 100ull << 20, 6000ull << 20, "data"));
  EXPECT_THROW(check_expansion("b.x3p", 100ull << 20, 6500ull << 20, "data"), FileError);
  EXPECT_THROW(check_memory("c.x3p", UINT64_MAX, "everything"), FileError);
}

TEST(OutputGroup, CommitsAllOrNothing) {
  const fs::path d = scratch();
  { std::ofstream(d / "a.txt") << "old a"; }
  {
    OutputGroup g;
    write_file_atomic((d / "a.txt").string(), std::string("new a"));
    EXPECT_EQ(slurp(d / "a.txt"), "old a");  // staged, not yet renamed
    EXPECT_THROW(write_file_atomic((d / "missing" / "b.txt").string(), std::string("b")),
                 FileError);
    // The group is dropped without commit (the failed run).
  }
  EXPECT_EQ(slurp(d / "a.txt"), "old a");
  for (const auto& e : fs::directory_iterator(d))
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
  {
    OutputGroup g;
    write_file_atomic((d / "a.txt").string(), std::string("new a"));
    write_file_atomic((d / "c.txt").string(), std::string("c"));
    g.commit();
  }
  EXPECT_EQ(slurp(d / "a.txt"), "new a");
  EXPECT_EQ(slurp(d / "c.txt"), "c");
  // Without a group, each file is committed at once.
  write_file_atomic((d / "c.txt").string(), std::string("c2"));
  EXPECT_EQ(slurp(d / "c.txt"), "c2");
  fs::remove_all(d);
}

TEST(ErrorContext, DataErrorsNameTheFile) {
  try {
    about_file("scan.x3p", []() -> int { throw InputError("too few valid samples"); });
    FAIL();
  } catch (const FileError& e) {
    EXPECT_EQ(e.path(), "scan.x3p");
    EXPECT_EQ(std::string(e.what()), "scan.x3p: too few valid samples");
  }
  EXPECT_EQ(about_file("x", [] { return 3; }), 3);
}

TEST(Readers, RefuseNonRegularFilesAndAbsurdHeights) {
  const fs::path d = scratch();
  const std::string fifo = (d / "pipe.x3p").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  try {
    read_surface(fifo);
    FAIL() << "a FIFO was read";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
  }
  Surface s(4, 4, 1e-6, 1e-6);
  for (double& z : s.z) z = 1e-8;
  s.sync_mask();
  write_surface(s, (d / "s.npy").string());
  EXPECT_NO_THROW(read_surface((d / "s.npy").string()));
  s.at(2, 1) = 1e308;
  write_surface(s, (d / "h.npy").string());
  try {
    read_surface((d / "h.npy").string());
    FAIL() << "a height of 1e308 m accepted";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("at sample (x 2, y 1) is absurd"), std::string::npos)
        << e.what();
  }
  fs::remove_all(d);
}

TEST(SceneCounts, SixtyFourBitAndBounded) {
  MicroSceneDesc d;
  d.width = d.height = 1e-3;
  d.materials.push_back({});
  EXPECT_THROW(add_cylinders(d, 1e-6, std::int64_t{4294967304}, 1e-6, 0, 1, 0), InputError);
  EXPECT_TRUE(d.capsules.empty());
  add_cylinders(d, 1e-6, 8, 1e-6, 0, 1, 0);
  EXPECT_EQ(d.capsules.size(), 8u);
  FiberParams f;
  f.count = std::int64_t{2000000000};
  EXPECT_THROW(add_fibers(d, f), InputError);
  EXPECT_EQ(d.capsules.size(), 8u);
  const nlohmann::json j = parse_json_text(
      R"({"tile": "1x1mm", "materials": {"m": {"type": "mirror"}},
          "objects": [{"type": "cylinders", "radius": "1um", "count": 4294967304,
                       "material": "m"}]})",
      "wrap.json");
  try {
    parse_micro_scene(j, ".", "wrap.json");
    FAIL() << "a count of 2^32 + 8 accepted";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("'count' is 4294967304"), std::string::npos) << e.what();
  }
}

TEST(Threads, ClampedToASaneMaximum) {
  EXPECT_EQ(resolve_thread_count(3), 3);
  EXPECT_EQ(resolve_thread_count(1000000), max_thread_count());
  EXPECT_GE(resolve_thread_count(0), 1);
  EXPECT_GE(max_thread_count(), 16);
}
