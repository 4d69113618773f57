// EXR and TIFF height-image readers. Fixtures: tests/data/height_* (see tests/data/README.md;
// made by tests/data/make_image_fixtures.cpp, whose expected_height() is mirrored here).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "microbrdf/error.hpp"
#include "microbrdf/io.hpp"
#include "microbrdf/surface.hpp"

using namespace microbrdf;
namespace fs = std::filesystem;

namespace {

const std::string kData = MICROBRDF_TEST_DATA;

// The generator's formula, stored as float32 in the files; NaN at (3, 2).
double expected_float(int ix, int iy) {
  if (ix == 3 && iy == 2) return NAN;
  return static_cast<double>(static_cast<float>((ix * 0.25 + iy * 1.5 - 3.0) * 1e-6));
}

ReadOptions spacing(double dx, double dy) {
  ReadOptions o;
  o.dx = dx;
  o.dy = dy;
  return o;
}

std::vector<std::uint8_t> slurp(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

fs::path temp_path(const std::string& file) {
  fs::path dir =
      fs::temp_directory_path() / ("microbrdf-test-images-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir / file;
}

void expect_formula(const Surface& s) {
  ASSERT_EQ(s.nx, 20u);
  ASSERT_EQ(s.ny, 12u);
  std::size_t wrong = 0;
  for (int iy = 0; iy < 12; ++iy)
    for (int ix = 0; ix < 20; ++ix) {
      double e = expected_float(ix, iy);
      double v = s.at(static_cast<std::size_t>(ix), static_cast<std::size_t>(iy));
      if (std::isnan(e) ? !std::isnan(v) : v != e) ++wrong;
    }
  EXPECT_EQ(wrong, 0u);
  EXPECT_EQ(s.valid_count(), 20u * 12u - 1u);
  EXPECT_FALSE(s.is_valid(s.index(3, 2)));
}

// Every truncation and a few byte flips of `file` must give FileError naming the file (or a
// valid surface), never anything else.
void hammer(const std::string& file, const std::string& ext) {
  auto bytes = slurp(file);
  auto p = temp_path("hammer" + ext);
  auto opt = spacing(1e-6, 1e-6);
  std::size_t errors = 0;
  for (std::size_t n = 0; n < bytes.size(); n += std::max<std::size_t>(1, bytes.size() / 97)) {
    std::ofstream(p, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(n));
    try {
      read_surface(p.string(), opt);
    } catch (const FileError& e) {
      ++errors;
      EXPECT_NE(std::string(e.what()).find(p.string()), std::string::npos) << e.what();
    }
  }
  EXPECT_GT(errors, 50u);
  for (std::size_t i = 0; i < bytes.size(); i += 13) {
    auto b = bytes;
    b[i] ^= 0xA5;
    try {
      read_surface_bytes(b, SurfaceFormat::Auto, "flipped" + ext, opt).check();
    } catch (const FileError& e) {
      EXPECT_NE(std::string(e.what()).find("flipped"), std::string::npos) << e.what();
    } catch (const InputError&) {
    }
  }
}

}  // namespace

TEST(format_images, ExrFloatZChannel) {
  Surface s = read_surface(kData + "/height_z_float.exr", spacing(2e-7, 3e-7));
  s.check();
  expect_formula(s);
  EXPECT_DOUBLE_EQ(s.dx, 2e-7);
  EXPECT_DOUBLE_EQ(s.dy, 3e-7);
  EXPECT_EQ(s.meta.format, "exr");
  EXPECT_EQ(s.meta.get("exr_channel"), "Z");
  EXPECT_EQ(s.meta.z_unit_in_file, "m");
}

TEST(format_images, ExrTiled) {
  Surface s = read_surface(kData + "/height_z_tiled.exr", spacing(1e-6, 1e-6));
  expect_formula(s);
}

TEST(format_images, ExrHalfRgbPicksRAndScalesUnit) {
  Surface s = read_surface(kData + "/height_rgb_half_um.exr", spacing(1e-6, 1e-6));
  ASSERT_EQ(s.nx, 10u);
  ASSERT_EQ(s.ny, 6u);
  EXPECT_EQ(s.meta.get("exr_channel"), "R");
  EXPECT_EQ(s.meta.get("exr_channel_type"), "half");
  EXPECT_EQ(s.meta.z_unit_in_file, "um");
  for (int iy = 0; iy < 6; ++iy)
    for (int ix = 0; ix < 10; ++ix)
      EXPECT_DOUBLE_EQ(s.at(ix, iy), (ix - 2.0 * iy) * 1e-6) << ix << "," << iy;
}

TEST(format_images, ExrNeedsSpacingAndRejectsCorruption) {
  try {
    read_surface(kData + "/height_z_float.exr");
    ADD_FAILURE() << "no spacing accepted";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("--spacing"), std::string::npos) << e.what();
  }
  // Also at the reader level (read_surface_bytes without options).
  EXPECT_THROW(read_surface_bytes(slurp(kData + "/height_z_float.exr"), SurfaceFormat::Exr, "m"),
               FileError);
  hammer(kData + "/height_z_float.exr", ".exr");
  hammer(kData + "/height_rgb_half_um.exr", ".exr");
  hammer(kData + "/height_z_tiled.exr", ".exr");
}

TEST(format_images, ExrHostileHeaderSizesAreRefusedBeforeOpenExrAllocates) {
  // OpenEXR 3.1 allocates a string attribute's declared size, and loses its place when a
  // fixed-size attribute declares another size; both were found by fuzz_exr.
  const auto good = slurp(kData + "/height_z_float.exr");
  auto patch = [&](const std::string& key, std::uint32_t size) {
    auto b = good;
    std::string text(b.begin(), b.end());
    auto at = text.find(key);
    EXPECT_NE(at, std::string::npos) << key;
    at += key.size();
    for (int i = 0; i < 4; ++i) b[at + i] = static_cast<std::uint8_t>(size >> (8 * i));
    return b;
  };
  auto opt = spacing(1e-6, 1e-6);
  for (const auto& b : {patch(std::string("comments\0string\0", 16), 0x7C7C7C7Cu),
                        patch(std::string("displayWindow\0box2i\0", 20), 0u),
                        patch(std::string("channels\0chlist\0", 16), 3u)}) {
    try {
      read_surface_bytes(b, SurfaceFormat::Exr, "hostile.exr", opt);
      ADD_FAILURE() << "accepted";
    } catch (const FileError& e) {
      EXPECT_NE(std::string(e.what()).find("corrupt"), std::string::npos) << e.what();
    }
  }
}

TEST(format_images, TiffFloatStripsAndTiles) {
  for (const char* f : {"/height_f32.tif", "/height_f32_tiled.tif"}) {
    SCOPED_TRACE(f);
    Surface s = read_surface(kData + f, spacing(5e-7, 5e-7));
    s.check();
    expect_formula(s);
    EXPECT_EQ(s.meta.format, "tiff");
    EXPECT_EQ(s.meta.get("tiff_sample_type"), "float32");
  }
  EXPECT_EQ(read_surface(kData + "/height_f32.tif", spacing(1, 1)).meta.comment,
            "microbrdf test fixture");
}

TEST(format_images, TiffUint16WithUnit) {
  Surface s = read_surface(kData + "/height_u16_nm.tif", spacing(1e-6, 1e-6));
  ASSERT_EQ(s.nx, 20u);
  ASSERT_EQ(s.ny, 12u);
  EXPECT_EQ(s.meta.z_unit_in_file, "nm");
  EXPECT_EQ(s.meta.get("tiff_sample_type"), "uint16");
  for (int iy = 0; iy < 12; ++iy)
    for (int ix = 0; ix < 20; ++ix)
      EXPECT_DOUBLE_EQ(s.at(ix, iy), (1000 + 7 * ix + 300 * iy) * 1e-9) << ix << "," << iy;
}

TEST(format_images, TiffRejectsRgbMissingSpacingAndCorruption) {
  try {
    read_surface(kData + "/height_rgb16.tif", spacing(1e-6, 1e-6));
    ADD_FAILURE() << "RGB accepted";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("samples per pixel"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_surface(kData + "/height_f32.tif"), FileError);
  EXPECT_THROW(read_surface_bytes(slurp(kData + "/height_f32.tif"), SurfaceFormat::Tiff, "m"),
               FileError);
  hammer(kData + "/height_f32.tif", ".tif");
  hammer(kData + "/height_f32_tiled.tif", ".tif");
  hammer(kData + "/height_u16_nm.tif", ".tif");
}
