// Digital Surf .sur reader: reference values from tests/data/README.md, hostile inputs.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "format_test_util.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/io.hpp"

using namespace microbrdf;
using namespace microbrdf::test;
namespace fs = std::filesystem;

namespace {

const std::string kFile = std::string(MICROBRDF_TEST_DATA) + "/sur-2.sur";

constexpr std::size_t kData = 512;
constexpr std::int32_t kMarker = 89118;  // zmin - 2

}  // namespace

TEST(format_sur, ReferenceValues) {
  Surface s = read_surface(kFile);
  EXPECT_EQ(s.nx, 563u);
  EXPECT_EQ(s.ny, 484u);
  EXPECT_NEAR(s.dx, 3.484e-6, 3.484e-6 * 1e-6);
  EXPECT_NEAR(s.dy, 3.484e-6, 3.484e-6 * 1e-6);
  Stats st = stats(s);
  EXPECT_EQ(st.invalid, 117u);
  // Reference table is in mm.
  EXPECT_NEAR(st.min, 0.008912e-3, 0.008912e-3 * 1e-5);
  EXPECT_NEAR(st.max, 0.010388e-3, 0.010388e-3 * 1e-5);
  EXPECT_NEAR(st.mean, 0.0101574e-3, 0.0101574e-3 * 1e-5);
  EXPECT_NEAR(st.sq, 1.75179e-05 * 1e-3, 1.75179e-05 * 1e-3 * 1e-5);
  EXPECT_NEAR(s.at(0, 0), 0.0101477e-3, 0.0101477e-3 * 1e-6);
  s.check();
}

TEST(format_sur, Metadata) {
  Surface s = read_surface(kFile);
  EXPECT_EQ(s.meta.format, "sur");
  EXPECT_EQ(s.meta.z_unit_in_file, "mm");
  EXPECT_EQ(s.meta.get("object_type"), "surface");
  EXPECT_EQ(s.meta.get("non_measured_points"), "117");
  EXPECT_EQ(s.meta.get("non_measured_marker_raw"), "89118");
  EXPECT_EQ(s.meta.get("point_size_bits"), "32");
  EXPECT_EQ(s.meta.date, "");  // the file states no date
}

TEST(format_sur, MarkerOnlyWithSpecialPoints) {
  auto b = load(kFile);
  put_le16(b, 86, 0);  // special_points = 0: the zmin - 2 values count as measured
  TempDir dir;
  Surface s = read_surface(dir.write("nospecial.sur", b));
  EXPECT_EQ(stats(s).invalid, 0u);
  EXPECT_NEAR(stats(s).min, kMarker * 1e-7 * 1e-3, kMarker * 1e-10 * 1e-6);
}

TEST(format_sur, UnitsAndOffsetAndCommentZone) {
  auto b = load(kFile);
  // dz unit "um" in Latin-1 (0xB5 'm'): heights become 1000x larger than with "mm".
  std::memset(b.data() + 212, 0, 16);
  b[212] = 0xB5;
  b[213] = 'm';
  // z offset of 5 (in the dz unit).
  float off = 5.0f;
  std::uint32_t bits;
  std::memcpy(&bits, &off, 4);
  put_le32(b, 474, bits);
  // A 16-byte comment zone shifts the data.
  put_le16(b, 334, 16);
  std::vector<std::uint8_t> c(b.begin(), b.begin() + kData);
  const char* text = "hello comment   ";
  c.insert(c.end(), text, text + 16);
  c.insert(c.end(), b.begin() + kData, b.end());
  TempDir dir;
  Surface s = read_surface(dir.write("um.sur", c));
  EXPECT_EQ(s.meta.z_unit_in_file, "um");
  EXPECT_EQ(s.meta.comment, "hello comment");
  EXPECT_NEAR(s.at(0, 0), (0.0101477 + 5) * 1e-6, 1e-12);
  EXPECT_EQ(stats(s).invalid, 117u);
}

TEST(format_sur, Int16Points) {
  // Build a 16-bit file from the header: 4 x 3 points.
  auto b = load(kFile);
  std::vector<std::uint8_t> h(b.begin(), b.begin() + kData);
  put_le16(h, 98, 16);
  put_le32(h, 100, static_cast<std::uint32_t>(-100));  // zmin
  put_le32(h, 108, 4);
  put_le32(h, 112, 3);
  put_le32(h, 116, 12);
  for (int i = 0; i < 12; ++i) {
    std::int16_t v = static_cast<std::int16_t>(i == 5 ? -102 : -50 + 10 * i);
    h.push_back(static_cast<std::uint8_t>(v));
    h.push_back(static_cast<std::uint8_t>(static_cast<std::uint16_t>(v) >> 8));
  }
  TempDir dir;
  Surface s = read_surface(dir.write("i16.sur", h));
  EXPECT_EQ(s.nx, 4u);
  EXPECT_EQ(s.ny, 3u);
  EXPECT_FALSE(s.is_valid(5));
  EXPECT_NEAR(s.at(0, 0), -50 * 1e-7 * 1e-3, 1e-15);
  EXPECT_NEAR(s.at(3, 2), 60 * 1e-7 * 1e-3, 1e-15);
}

TEST(format_sur, TruncatedFilesAreErrors) {
  auto b = load(kFile);
  ASSERT_EQ(b.size(), 1090480u);
  TempDir dir;
  for (std::size_t len : {std::size_t{0}, std::size_t{10}, std::size_t{200}, std::size_t{511},
                          std::size_t{512}, std::size_t{600}, b.size() / 2, b.size() - 1}) {
    std::vector<std::uint8_t> cut(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(len));
    expect_file_error(dir.write("cut" + std::to_string(len) + ".sur", cut));
  }
  std::vector<std::uint8_t> cut(b.begin(), b.end() - 1);
  expect_file_error(dir.write("last.sur", cut), "563 x 484 int32");
}

TEST(format_sur, HostileHeaders) {
  const auto b = load(kFile);
  TempDir dir;
  auto patched = [&](const char* file, auto&& patch, const std::string& needle) {
    auto h = b;
    patch(h);
    expect_file_error(dir.write(file, h), needle);
  };
  patched(
      "huge.sur",
      [](auto& h) {
        put_le32(h, 108, 0x7FFFFFFF);
        put_le32(h, 112, 0x7FFFFFFF);
      },
      "absurdly large");
  patched(
      "big.sur", [](auto& h) { put_le32(h, 112, 100000); }, "truncated");
  patched(
      "neg.sur", [](auto& h) { put_le32(h, 108, static_cast<std::uint32_t>(-5)); }, "grid");
  patched(
      "psize.sur", [](auto& h) { put_le16(h, 98, 8); }, "point size");
  patched(
      "mac.sur", [](auto& h) { put_le16(h, 12, 257); }, "Macintosh");
  patched(
      "type.sur", [](auto& h) { put_le16(h, 18, 3); }, "object type");
  patched(
      "dz.sur", [](auto& h) { put_le32(h, 128, 0); }, "dz");
  patched(
      "unit.sur", [](auto& h) { std::memcpy(h.data() + 212, "nA\0", 3); }, "unit");
  patched(
      "zones.sur",
      [](auto& h) {
        put_le16(h, 334, 65535);
        put_le16(h, 336, 65535);
      },
      "truncated");
  patched(
      "magic.sur", [](auto& h) { h[0] = 'X'; }, "");
}
