// Zygo .datx (HDF5) reader: reference values from tests/data/README.md, hostile inputs.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "format_test_util.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/io.hpp"
#include "surface/isolated_reader.hpp"

using namespace microbrdf;
using namespace microbrdf::test;
namespace fs = std::filesystem;

namespace {

const std::string kFile = std::string(MICROBRDF_TEST_DATA) + "/zygo_test.datx";

// Byte offset of the first occurrence of `pattern` in `b` (npos when absent).
std::size_t find_bytes(const std::vector<std::uint8_t>& b,
                       const std::vector<std::uint8_t>& pattern) {
  auto it = std::search(b.begin(), b.end(), pattern.begin(), pattern.end());
  return it == b.end() ? std::string::npos : static_cast<std::size_t>(it - b.begin());
}

}  // namespace

TEST(format_datx, ReferenceValues) {
  Surface s = read_surface(kFile);
  EXPECT_EQ(s.nx, 33u);
  EXPECT_EQ(s.ny, 259u);
  EXPECT_NEAR(s.dx, 1e-3, 1e-9);  // as stored (looks uncalibrated, see metadata)
  EXPECT_NEAR(s.dy, 1e-3, 1e-9);
  Stats st = stats(s);
  EXPECT_EQ(st.invalid, 776u);
  EXPECT_NEAR(st.min, -1.46475e-07, 1.46475e-07 * 1e-5);
  EXPECT_NEAR(st.max, 3.06555e-07, 3.06555e-07 * 1e-5);
  EXPECT_NEAR(st.mean, 2.86961e-08, 2.86961e-08 * 1e-5);
  EXPECT_NEAR(st.sq, 8.08177e-08, 8.08177e-08 * 1e-5);
  EXPECT_NEAR(s.at(0, 0), 1.253306e-07, 1.253306e-07 * 1e-6);
  s.check();
}

TEST(format_datx, Metadata) {
  Surface s = read_surface(kFile);
  EXPECT_EQ(s.meta.format, "datx");
  EXPECT_EQ(s.meta.z_unit_in_file, "Fringes");
  EXPECT_NE(s.meta.instrument.find("Zygo GPI"), std::string::npos) << s.meta.instrument;
  EXPECT_NE(s.meta.instrument.find("651365"), std::string::npos) << s.meta.instrument;
  EXPECT_NEAR(std::stod(s.meta.get("wavelength_m")), 632.8e-9, 1e-12);
  EXPECT_EQ(s.meta.get("interferometric_scale_factor"), "0.5");
  EXPECT_EQ(s.meta.get("lateral_resolution_source"), "X/Y Converter");
  EXPECT_FALSE(s.meta.get("lateral_resolution_note").empty());
  EXPECT_EQ(s.meta.get("acquisition_mode"), "PSI");
  EXPECT_EQ(s.meta.get("software"), "MetroPro 8.3.3");
  EXPECT_EQ(s.meta.get("no_data_points"), "776");
  EXPECT_EQ(s.meta.date, "");  // the time stamp is an unset placeholder
  EXPECT_EQ(s.meta.get("time_stamp_raw"), "719529");
}

TEST(format_datx, SpacingOverride) {
  ReadOptions opt;
  opt.dx = opt.dy = 50e-6;
  Surface s = read_surface(kFile, opt);
  EXPECT_DOUBLE_EQ(s.dx, 50e-6);
}

TEST(format_datx, TruncatedFilesAreErrors) {
  auto b = load(kFile);
  ASSERT_EQ(b.size(), 131672u);
  TempDir dir;
  for (std::size_t len : {std::size_t{0}, std::size_t{10}, std::size_t{47}, std::size_t{600},
                          std::size_t{4096}, b.size() / 2, b.size() - 1}) {
    std::vector<std::uint8_t> cut(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(len));
    expect_file_error(dir.write("cut" + std::to_string(len) + ".datx", cut));
  }
}

TEST(format_datx, HostileDimensions) {
  // The dataspace message of the surface stores the dims (259, 33) as two little-endian
  // uint64 in a row; patch them to absurd values.
  const auto b = load(kFile);
  std::vector<std::uint8_t> dims(16, 0);
  dims[0] = 259 & 0xFF;
  dims[1] = 259 >> 8;
  dims[8] = 33;
  const std::size_t at = find_bytes(b, dims);
  ASSERT_NE(at, std::string::npos);
  TempDir dir;
  {
    auto h = b;
    for (int i = 0; i < 8; ++i) h[at + i] = 0xFF;
    expect_file_error(dir.write("huge.datx", h));
  }
  {
    auto h = b;  // 100000 x 100000: over the file size
    std::uint64_t v = 100000;
    for (int i = 0; i < 8; ++i) {
      h[at + i] = static_cast<std::uint8_t>(v >> (8 * i));
      h[at + 8 + i] = static_cast<std::uint8_t>(v >> (8 * i));
    }
    expect_file_error(dir.write("big.datx", h));
  }
}

TEST(format_datx, CorruptBytesNeverCrash) {
  // Overwrite 64-byte windows across the file: each result is a surface or a FileError.
  const auto b = load(kFile);
  std::size_t errors = 0, reads = 0;
  for (std::size_t off = 0; off + 64 <= b.size(); off += 2048) {
    auto h = b;
    for (std::size_t i = 0; i < 64; ++i) h[off + i] = static_cast<std::uint8_t>(0xA5 ^ i);
    try {
      Surface s = read_surface_bytes(h, SurfaceFormat::Datx, "corrupt.datx");
      s.check();
      ++reads;
    } catch (const FileError& e) {
      EXPECT_NE(std::string(e.what()).find("corrupt.datx"), std::string::npos);
      ++errors;
    }
  }
  EXPECT_GT(errors, 0u);
  EXPECT_GT(reads, 0u);
}

TEST(format_datx, NotHdf5) {
  std::vector<std::uint8_t> junk(1000, 0x42);
  EXPECT_THROW(read_surface_bytes(junk, SurfaceFormat::Datx, "junk.datx"), FileError);
}

TEST(format_datx, CorruptGlobalHeapIsRejected) {
  // A variable-length string object whose size runs past its global heap collection made
  // libhdf5 1.10 (H5HG_read) copy ~160 MB past a heap buffer (found by fuzz_datx).
  auto b = load(kFile);
  const std::size_t gcol = find_bytes(b, {'G', 'C', 'O', 'L'});
  ASSERT_NE(gcol, std::string::npos);
  const std::size_t first_object = gcol + 16;  // 16-byte collection header
  const std::uint64_t huge = 0x0A000006;
  for (int i = 0; i < 8; ++i) b[first_object + 8 + i] = static_cast<std::uint8_t>(huge >> (8 * i));
  TempDir dir;
  expect_file_error(dir.write("heap.datx", b), "global heap");
}

// Files that crash, leak or blow up libhdf5 1.10 in-process (fuzz/repro/) never take the caller
// down: each ends as a consistent Surface (the guards made it readable) or a FileError naming
// the file (the decoder runs in a child process).
TEST(format_datx, LibraryFailuresAreContained) {
  const std::string dir = std::string(MICROBRDF_TEST_DATA) + "/../../fuzz/repro";
  int seen = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().extension() != ".datx") continue;
    ++seen;
    try {
      auto s = microbrdf::read_surface(e.path().string());
      EXPECT_NO_THROW(s.check()) << e.path();
    } catch (const microbrdf::FileError& err) {
      EXPECT_NE(std::string(err.what()).find(e.path().filename().string()), std::string::npos)
          << err.what();
    }
  }
  EXPECT_GE(seen, 5);
}

// A decoder that crashes in the child becomes a FileError in the caller.
TEST(format_datx, CrashInDecoderBecomesFileError) {
  try {
    microbrdf::detail::read_isolated("crash.datx", "testlib", []() -> microbrdf::Surface {
      std::raise(SIGSEGV);
      return {};
    });
    ADD_FAILURE() << "no error";
  } catch (const microbrdf::FileError& e) {
    EXPECT_NE(std::string(e.what()).find("crash.datx: testlib crashed"), std::string::npos)
        << e.what();
  }
  try {
    microbrdf::detail::read_isolated(
        "slow.datx", "testlib",
        []() -> microbrdf::Surface {
          ::sleep(5);
          return {};
        },
        1);
    ADD_FAILURE() << "no error";
  } catch (const microbrdf::FileError& e) {
    EXPECT_NE(std::string(e.what()).find("did not finish"), std::string::npos) << e.what();
  }
}
