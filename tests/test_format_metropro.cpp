// Zygo MetroPro .dat reader: reference values from tests/data/README.md, hostile inputs.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
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

const std::string kFile = std::string(MICROBRDF_TEST_DATA) + "/metropro-1.dat";

constexpr std::size_t kHeader = 834;
constexpr std::size_t kPhaseOffset = kHeader + 640 * 480 * 2;

}  // namespace

TEST(format_metropro, ReferenceValues) {
  Surface s = read_surface(kFile);
  EXPECT_EQ(s.nx, 640u);
  EXPECT_EQ(s.ny, 480u);
  EXPECT_NEAR(s.dx, 1.0982520e-6, 1e-12);
  EXPECT_NEAR(s.dy, 1.0982520e-6, 1e-12);
  Stats st = stats(s);
  EXPECT_EQ(st.invalid, 0u);
  EXPECT_NEAR(st.min, 5.01083e-05, 5.01083e-05 * 1e-5);
  EXPECT_NEAR(st.max, 5.14713e-05, 5.14713e-05 * 1e-5);
  EXPECT_NEAR(st.mean, 5.07404e-05, 5.07404e-05 * 1e-5);
  EXPECT_NEAR(st.sq, 7.52882e-08, 7.52882e-08 * 1e-5);
  EXPECT_NEAR(s.at(0, 0), 5.057531e-05, 5.057531e-05 * 1e-6);
  s.check();
}

TEST(format_metropro, Metadata) {
  Surface s = read_surface(kFile);
  EXPECT_EQ(s.meta.format, "dat");
  EXPECT_NE(s.meta.instrument.find("Zygo"), std::string::npos);
  EXPECT_NE(s.meta.instrument.find("8.1.5"), std::string::npos);
  EXPECT_EQ(s.meta.date, "2011-07-23T16:49:36Z");
  EXPECT_EQ(s.meta.get("objective"), "20X  Mirau");
  EXPECT_NEAR(std::stod(s.meta.get("wavelength_m")), 570e-9, 1e-12);
  EXPECT_EQ(s.meta.get("phase_resolution_counts_per_wave"), "32768");
  EXPECT_EQ(s.meta.get("uncalibrated_lateral"), "");
  EXPECT_FALSE(s.meta.z_unit_in_file.empty());
}

TEST(format_metropro, InvalidPhaseAndSignFlag) {
  auto b = load(kFile);
  put_be32(b, kPhaseOffset, 2147483640u);      // sample (0, 0) invalid
  put_be32(b, kPhaseOffset + 4, 0x7FFFFFFFu);  // sample (1, 0) invalid
  put_be16(b, 232, 1);                         // data inverted
  TempDir dir;
  Surface s = read_surface(dir.write("patched.dat", b));
  EXPECT_EQ(stats(s).invalid, 2u);
  EXPECT_FALSE(s.is_valid(0));
  EXPECT_TRUE(std::isnan(s.at(1, 0)));
  // Negated heights: the whole surface now lies below zero.
  EXPECT_NEAR(stats(s).max, -5.01083e-05, 5.01083e-05 * 1e-5);
}

TEST(format_metropro, UncalibratedNeedsSpacing) {
  auto b = load(kFile);
  put_be32(b, 184, 0);  // lateral_res = 0.0f
  TempDir dir;
  std::string p = dir.write("uncal.dat", b);
  expect_file_error(p, "--spacing");
  ReadOptions opt;
  opt.dx = opt.dy = 2e-6;
  Surface s = read_surface(p, opt);
  EXPECT_EQ(s.meta.get("uncalibrated_lateral"), "true");
  EXPECT_DOUBLE_EQ(s.dx, 2e-6);
  EXPECT_EQ(s.nx, 640u);
}

TEST(format_metropro, TruncatedFilesAreErrors) {
  auto b = load(kFile);
  ASSERT_EQ(b.size(), 1844034u);
  TempDir dir;
  for (std::size_t len : {std::size_t{0}, std::size_t{3}, std::size_t{10}, std::size_t{600},
                          kHeader, kHeader + 1000, kPhaseOffset, b.size() / 2, b.size() - 1}) {
    std::vector<std::uint8_t> cut(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(len));
    expect_file_error(dir.write("cut" + std::to_string(len) + ".dat", cut));
  }
  std::vector<std::uint8_t> cut(b.begin(), b.end() - 1);
  expect_file_error(dir.write("last.dat", cut), "int32 phase samples");
}

TEST(format_metropro, HostileHeaders) {
  const auto b = load(kFile);
  TempDir dir;
  {
    auto h = b;  // absurd phase grid
    put_be16(h, 68, 65535);
    put_be16(h, 70, 65535);
    expect_file_error(dir.write("huge.dat", h), "65535 x 65535");
  }
  {
    auto h = b;  // absurd intensity block
    put_be16(h, 56, 65535);
    expect_file_error(dir.write("buckets.dat", h), "intensity");
  }
  {
    auto h = b;  // header larger than the file
    put_be32(h, 6, 0xFFFFFFF0u);
    expect_file_error(dir.write("hdr.dat", h), "header size");
  }
  {
    auto h = b;  // header too small
    put_be32(h, 6, 100);
    expect_file_error(dir.write("small.dat", h), "header size");
  }
  {
    auto h = b;  // zero-sized phase grid
    put_be16(h, 68, 0);
    expect_file_error(dir.write("empty.dat", h), "phase");
  }
  {
    auto h = b;  // unknown phase resolution
    put_be16(h, 218, 7);
    expect_file_error(dir.write("res.dat", h), "phase resolution");
  }
  {
    auto h = b;  // NaN wavelength
    put_be32(h, 168, 0x7FC00000u);
    expect_file_error(dir.write("wl.dat", h), "wavelength");
  }
  {
    auto h = b;  // bad magic
    h[3] = 0x72;
    try {
      read_surface_bytes(h, SurfaceFormat::MetroProDat, "bad-magic.dat");
      ADD_FAILURE();
    } catch (const FileError& e) {
      EXPECT_NE(std::string(e.what()).find("magic"), std::string::npos);
    }
  }
}
