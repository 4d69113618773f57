// Sensofar .plu reader: reference values from tests/data/README.md, hostile inputs.
// The fixture is plu-1.plu without its trailing camera image (tests/data/README.md); the full file
// is checked too when the optional extra data folder holds it (MICROBRDF_EXTRA_DATA).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "format_test_util.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/io.hpp"

using namespace microbrdf;
using namespace microbrdf::test;
namespace fs = std::filesystem;

namespace {

const std::string kFile = std::string(MICROBRDF_TEST_DATA) + "/plu-1-heights.plu";

constexpr std::size_t kData = 508;

void expect_reference_values(const std::string& path) {
  Surface s = read_surface(path);
  EXPECT_EQ(s.nx, 768u);
  EXPECT_EQ(s.ny, 576u);
  EXPECT_NEAR(s.dx, 1.66e-6, 1.66e-6 * 1e-6);
  EXPECT_NEAR(s.dy, 1.66e-6, 1.66e-6 * 1e-6);
  Stats st = stats(s);
  EXPECT_EQ(st.invalid, 0u);
  // Reference table is in um.
  EXPECT_NEAR(st.min, -111.23e-6, 111.23e-6 * 1e-5);
  EXPECT_NEAR(st.max, -101.215e-6, 101.215e-6 * 1e-5);
  EXPECT_NEAR(st.mean, -106.238e-6, 106.238e-6 * 1e-5);
  EXPECT_NEAR(st.sq, 2.83439e-6, 2.83439e-6 * 1e-5);
  EXPECT_NEAR(s.at(0, 0), -111.2266e-6, 111.2266e-6 * 1e-6);
  s.check();
}

}  // namespace

TEST(format_plu, ReferenceValues) { expect_reference_values(kFile); }

#ifdef MICROBRDF_EXTRA_DATA
// The full 3.2 MB file (with the camera image after the height layer) reads the same.
TEST(format_plu, FullFileFromExtraData) {
  const std::string full = std::string(MICROBRDF_EXTRA_DATA) + "/plu-1.plu";
  if (!fs::exists(full)) GTEST_SKIP() << full << " not in the extra data folder";
  expect_reference_values(full);
  EXPECT_EQ(read_surface(full).z, read_surface(kFile).z);
}
#endif

TEST(format_plu, Metadata) {
  Surface s = read_surface(kFile);
  EXPECT_EQ(s.meta.format, "plu");
  EXPECT_EQ(s.meta.instrument, "Sensofar");
  EXPECT_EQ(s.meta.date, "2023-03-10T16:35:59");
  EXPECT_EQ(s.meta.z_unit_in_file, "um");
  EXPECT_EQ(s.meta.get("objective_index"), "14");
  EXPECT_EQ(s.meta.get("z_planes"), "23");
  EXPECT_EQ(s.meta.get("layers_in_file"), "1");
}

TEST(format_plu, UndefinedPoints) {
  auto b = load(kFile);
  put_f32(b, kData, 1000001.0f);
  put_f32(b, kData + 4 * 769, 1000001.0f);
  put_f32(b, kData + 8, std::numeric_limits<float>::quiet_NaN());
  TempDir dir;
  Surface s = read_surface(dir.write("undef.plu", b));
  EXPECT_EQ(stats(s).invalid, 3u);
  EXPECT_FALSE(s.is_valid(s.index(1, 1)));
  EXPECT_TRUE(s.is_valid(s.index(1, 0)));
  EXPECT_EQ(s.meta.get("undefined_points"), "2");
}

TEST(format_plu, TruncatedFilesAreErrors) {
  auto b = load(kFile);
  TempDir dir;
  const std::size_t layer_end = kData + 768 * 576 * 4;
  for (std::size_t len : {std::size_t{0}, std::size_t{10}, std::size_t{400}, std::size_t{507},
                          std::size_t{600}, layer_end / 2, layer_end - 1}) {
    std::vector<std::uint8_t> cut(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(len));
    expect_file_error(dir.write("cut" + std::to_string(len) + ".plu", cut));
  }
  std::vector<std::uint8_t> cut(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(layer_end - 1));
  expect_file_error(dir.write("last.plu", cut), "768 x 576 float32");
  // Cutting after the height layer (min/max, camera image) still reads.
  std::vector<std::uint8_t> ok(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(layer_end));
  EXPECT_EQ(read_surface(dir.write("layer-only.plu", ok)).nx, 768u);
}

TEST(format_plu, HostileHeaders) {
  // Only the first 600 bytes are needed to hit every header check.
  auto full = load(kFile);
  const std::vector<std::uint8_t> b(full.begin(), full.begin() + 600);
  TempDir dir;
  auto patched = [&](const char* file, auto&& patch, const std::string& needle) {
    auto h = b;
    patch(h);
    expect_file_error(dir.write(file, h), needle);
  };
  patched(
      "huge.plu",
      [](auto& h) {
        put_le32(h, 500, 0xFFFFFFFF);
        put_le32(h, 504, 0xFFFFFFFF);
      },
      "absurdly large");
  patched(
      "big.plu", [](auto& h) { put_le32(h, 500, 1000); }, "truncated");
  patched(
      "zero.plu", [](auto& h) { put_le32(h, 504, 0); }, "empty grid");
  patched(
      "type.plu", [](auto& h) { put_le32(h, 428, 1); }, "measurement type");
  patched(
      "layers.plu", [](auto& h) { h[489] = 0; }, "no data layer");
  patched(
      "pixel.plu", [](auto& h) { put_f32(h, 404, -1.0f); }, "pixel size");
}

TEST(format_plu, ZeroPixelSizeNeedsSpacing) {
  auto b = load(kFile);
  put_f32(b, 404, 0.0f);
  TempDir dir;
  expect_file_error(dir.write("nopix.plu", b), "--spacing");
}
