// Libraries loaded when first used (core/runtime_library.hpp): the loader's messages, and that
// each of libhdf5, libtiff and Cairo is mapped by this process only once its reader or a plot
// needs it. The maps are read from /proc/self/maps, not from the loader's own bookkeeping.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/bitmap_font.hpp"
#include "core/runtime_library.hpp"
#include "microbrdf/io.hpp"

using namespace microbrdf;

namespace {

// True when a file whose name starts with `prefix` is mapped into this process.
bool mapped(const std::string& prefix) {
  std::ifstream maps("/proc/self/maps");
  std::string line;
  while (std::getline(maps, line)) {
    const auto slash = line.rfind('/');
    if (slash != std::string::npos && line.compare(slash + 1, prefix.size(), prefix) == 0)
      return true;
  }
  return false;
}

}  // namespace

TEST(RuntimeLibrary, MissingLibraryNamesSonameAndPackage) {
  double* slot = nullptr;
  const std::string e = detail::load_runtime_library("libmicrobrdf-no-such-library.so.7",
                                                     "the package libnothing7", {{"sin", &slot}});
  EXPECT_NE(e.find("libmicrobrdf-no-such-library.so.7 cannot be loaded"), std::string::npos) << e;
  EXPECT_NE(e.find("install the package libnothing7"), std::string::npos) << e;
}

TEST(RuntimeLibrary, MissingSymbolIsListed) {
  void* sin_slot = nullptr;
  void* bogus_slot = nullptr;
  const std::string e = detail::load_runtime_library(
      "libm.so.6", "libc6", {{"sin", &sin_slot}, {"microbrdf_no_such_symbol", &bogus_slot}});
  EXPECT_NE(e.find("lacks microbrdf_no_such_symbol"), std::string::npos) << e;
  EXPECT_EQ(e.find("sin,"), std::string::npos) << e;  // sin exists: not listed
}

TEST(RuntimeLibrary, FunctionsAreCallableThroughTheirSlots) {
  double (*cos_fn)(double) = nullptr;
  ASSERT_EQ(detail::load_runtime_library("libm.so.6", "libc6", {{"cos", &cos_fn}}), "");
  ASSERT_NE(cos_fn, nullptr);
  EXPECT_DOUBLE_EQ(cos_fn(0.0), 1.0);
}

// Each test runs in its own process under ctest (gtest_discover_tests), so "not mapped yet" is
// this process's state at the start.
TEST(RuntimeLibrary, LibtiffIsMappedOnlyWhenATiffIsRead) {
  ASSERT_FALSE(mapped("libtiff.so")) << "libtiff is mapped at process start";
  const Surface dat = read_surface(std::string(MICROBRDF_TEST_DATA) + "/metropro-1.dat");
  EXPECT_GT(dat.nx, 0u);
  EXPECT_FALSE(mapped("libtiff.so")) << "reading a MetroPro .dat loaded libtiff";
  ReadOptions o;
  o.dx = o.dy = 1e-6;
  const Surface tif = read_surface(std::string(MICROBRDF_TEST_DATA) + "/height_f32.tif", o);
  EXPECT_GT(tif.nx, 0u);
  EXPECT_TRUE(mapped("libtiff.so"));
}

TEST(RuntimeLibrary, CairoIsMappedOnlyWhenTextIsDrawn) {
  ASSERT_FALSE(mapped("libcairo.so")) << "Cairo is mapped at process start";
  EXPECT_GT(detail::text_width("0.5 um", 2), 0u);
  EXPECT_TRUE(mapped("libcairo.so"));
}

TEST(RuntimeLibrary, Libhdf5IsMappedOnlyWhenADatxIsRead) {
  // Loaded before the reader forks its decoding child (surface/isolated_reader.hpp).
  ASSERT_FALSE(mapped("libhdf5")) << "libhdf5 is mapped at process start";
  const Surface dat = read_surface(std::string(MICROBRDF_TEST_DATA) + "/metropro-1.dat");
  EXPECT_GT(dat.nx, 0u);
  EXPECT_FALSE(mapped("libhdf5")) << "reading a MetroPro .dat loaded libhdf5";
  const Surface s = read_surface(std::string(MICROBRDF_TEST_DATA) + "/zygo_test.datx");
  EXPECT_EQ(s.nx, 33u);
  EXPECT_TRUE(mapped("libhdf5"));
}

TEST(RuntimeLibrary, FailedLoadLeavesNoSlotFilled) {
  void* sin_slot = reinterpret_cast<void*>(0x1);
  void* bogus_slot = nullptr;
  const std::string e = detail::load_runtime_library(
      "libm.so.6", "libc6", {{"sin", &sin_slot}, {"microbrdf_no_such_symbol", &bogus_slot}});
  EXPECT_FALSE(e.empty());
  EXPECT_EQ(sin_slot, nullptr);  // not left pointing into a library that was closed again
  EXPECT_EQ(bogus_slot, nullptr);
}
