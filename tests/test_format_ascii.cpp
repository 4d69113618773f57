// ASCII XYZ and grid/matrix readers and writers.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "microbrdf/error.hpp"
#include "microbrdf/io.hpp"
#include "microbrdf/surface.hpp"

using namespace microbrdf;
namespace fs = std::filesystem;

namespace {

fs::path temp_path(const std::string& file) {
  fs::path dir = fs::temp_directory_path() / ("microbrdf-test-ascii-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir / file;
}

void spit(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

Surface random_surface(std::size_t nx, std::size_t ny, unsigned seed) {
  Surface s(nx, ny, 1.1e-7, 1.3e-7);
  s.x0 = -3.3e-6;
  s.y0 = 7.7e-7;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1e-7);
  for (auto& z : s.z) z = g(rng);
  for (std::size_t i = 2; i < s.size(); i += 9) s.invalidate(i);
  s.meta.comment = "ascii round trip";
  return s;
}

std::uint64_t bits(double d) { return std::bit_cast<std::uint64_t>(d); }

void expect_bit_equal(const Surface& a, const Surface& b) {
  ASSERT_EQ(a.nx, b.nx);
  ASSERT_EQ(a.ny, b.ny);
  EXPECT_EQ(bits(a.dx), bits(b.dx));
  EXPECT_EQ(bits(a.dy), bits(b.dy));
  EXPECT_EQ(bits(a.x0), bits(b.x0));
  EXPECT_EQ(bits(a.y0), bits(b.y0));
  EXPECT_EQ(a.valid, b.valid);
  std::size_t differ = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a.is_valid(i) && bits(a.z[i]) != bits(b.z[i])) ++differ;
  EXPECT_EQ(differ, 0u);
}

ReadOptions spacing(double dx, double dy) {
  ReadOptions o;
  o.dx = dx;
  o.dy = dy;
  return o;
}

std::string error_of(const fs::path& p, const ReadOptions& o = {}) {
  try {
    read_surface(p.string(), o);
  } catch (const FileError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(format_ascii, GridRoundTripIsBitExact) {
  Surface s = random_surface(31, 19, 3);
  auto p = temp_path("rt.txt");
  write_surface(s, p.string());
  Surface r = read_surface(p.string());  // the header carries the spacing: no --spacing needed
  r.check();
  expect_bit_equal(s, r);
  EXPECT_EQ(r.meta.format, "txt");
  EXPECT_EQ(r.meta.comment, "ascii round trip");
  EXPECT_EQ(r.meta.z_unit_in_file, "m");
  // read -> write -> read again is still exact
  auto p2 = temp_path("rt2.asc");
  write_surface(r, p2.string(), SurfaceFormat::AsciiGrid);
  expect_bit_equal(s, read_surface(p2.string()));
}

TEST(format_ascii, XyzRoundTripIsBitExact) {
  Surface s = random_surface(23, 14, 4);
  auto p = temp_path("rt.xyz");
  write_surface(s, p.string());
  Surface r = read_surface(p.string());
  r.check();
  expect_bit_equal(s, r);
  EXPECT_EQ(r.meta.format, "xyz");
  // Same content in a .txt is recognised as XYZ by the header.
  auto p2 = temp_path("rt_xyz.txt");
  fs::copy_file(p, p2, fs::copy_options::overwrite_existing);
  expect_bit_equal(s, read_surface(p2.string()));
}

TEST(format_ascii, XyzAnyOrderUnitsAndHoles) {
  // 4 x 3 grid, dx = 0.5 um, dy = 2 um, origin (10 um, -1 um); shuffled, comma separated,
  // one point missing and one NaN.
  std::vector<std::string> lines;
  for (int iy = 0; iy < 3; ++iy)
    for (int ix = 0; ix < 4; ++ix) {
      if (ix == 1 && iy == 2) continue;  // missing
      char b[100];
      if (ix == 3 && iy == 0)
        std::snprintf(b, sizeof b, "%g, %g, NaN", 10 + 0.5 * ix, -1 + 2.0 * iy);
      else
        std::snprintf(b, sizeof b, "%g, %g, %g", 10 + 0.5 * ix, -1 + 2.0 * iy, ix + 10.0 * iy);
      lines.push_back(b);
    }
  std::mt19937 rng(1);
  std::shuffle(lines.begin(), lines.end(), rng);
  std::string text = "# exported by some instrument\n# units: um\nx,y,z\n";
  for (auto& l : lines) text += l + "\r\n";
  auto p = temp_path("shuffled.csv");
  spit(p, text);
  Surface s = read_surface(p.string());
  s.check();
  EXPECT_EQ(s.meta.format, "xyz");
  ASSERT_EQ(s.nx, 4u);
  ASSERT_EQ(s.ny, 3u);
  EXPECT_NEAR(s.dx, 0.5e-6, 1e-18);
  EXPECT_NEAR(s.dy, 2e-6, 1e-18);
  EXPECT_NEAR(s.x0, 10e-6, 1e-18);
  EXPECT_NEAR(s.y0, -1e-6, 1e-18);
  EXPECT_FALSE(s.is_valid(s.index(3, 0)));
  EXPECT_FALSE(s.is_valid(s.index(1, 2)));
  EXPECT_EQ(s.valid_count(), 10u);
  EXPECT_NEAR(s.at(2, 1), 12e-6, 1e-18);
  EXPECT_EQ(s.meta.z_unit_in_file, "um");
  EXPECT_TRUE(s.meta.get("unit_warning").empty());
}

TEST(format_ascii, XyzToleratesPrintNoise) {
  // Coordinates printed with 6 significant digits, as many instruments do.
  std::string text;
  for (int iy = 0; iy < 5; ++iy)
    for (int ix = 0; ix < 40; ++ix) {
      char b[100];
      std::snprintf(b, sizeof b, "%.6g %.6g %.6g\n", 1.234e-3 + ix * 1.37e-7, -4.1e-4 + iy * 2.9e-7,
                    1e-9 * ix);
      text += b;
    }
  auto p = temp_path("noisy.xyz");
  spit(p, text);
  Surface s = read_surface(p.string());
  EXPECT_EQ(s.nx, 40u);
  EXPECT_EQ(s.ny, 5u);
  EXPECT_NEAR(s.dx, 1.37e-7, 1e-9);
  EXPECT_NEAR(s.dy, 2.9e-7, 1e-9);
  EXPECT_EQ(s.valid_count(), 200u);
  EXPECT_FALSE(s.meta.get("unit_warning").empty());
}

TEST(format_ascii, XyzRejectsIrregularGridAndDuplicates) {
  auto p = temp_path("irregular.xyz");
  spit(p, "0 0 1\n1 0 1\n2.5 0 1\n0 1 1\n1 1 1\n2.5 1 1\n");
  std::string e = error_of(p);
  EXPECT_NE(e.find(p.string()), std::string::npos) << e;
  EXPECT_NE(e.find("regular grid"), std::string::npos) << e;
  spit(p, "0 0 1\n1 0 1\n0 1 1\n1 1 1\n1 1 2\n");
  e = error_of(p);
  EXPECT_NE(e.find("repeats"), std::string::npos) << e;
  spit(p, "0 0\n1 0\n");
  EXPECT_NE(error_of(p).find("3 values"), std::string::npos);
}

TEST(format_ascii, MatrixNeedsSpacingUnlessHeader) {
  auto p = temp_path("matrix.txt");
  spit(p, "% a plain matrix\n1 2 3 4\n5 - *** 8\n9 10 nan 12\n");
  std::string e = error_of(p);
  EXPECT_NE(e.find("--spacing"), std::string::npos) << e;
  EXPECT_NE(e.find(p.string()), std::string::npos) << e;
  Surface s = read_surface(p.string(), spacing(2e-6, 3e-6));
  EXPECT_EQ(s.meta.format, "txt");
  EXPECT_EQ(s.nx, 4u);
  EXPECT_EQ(s.ny, 3u);
  EXPECT_DOUBLE_EQ(s.dx, 2e-6);
  EXPECT_DOUBLE_EQ(s.dy, 3e-6);
  EXPECT_DOUBLE_EQ(s.at(3, 2), 12.0);
  EXPECT_EQ(s.valid_count(), 9u);
  // A header with dx_m and a z unit.
  spit(p, "# dx_m = 1e-6\n# z_unit = nm\n1;2;3\n4;5;6\n");
  s = read_surface(p.string());
  EXPECT_DOUBLE_EQ(s.dx, 1e-6);
  EXPECT_DOUBLE_EQ(s.dy, 1e-6);
  EXPECT_DOUBLE_EQ(s.at(2, 1), 6e-9);
  // Semicolon-separated lines use a decimal comma.
  spit(p, "# dx_m = 1e-6\n1,5;2,25;-3\n4;5,5;6e-1\n");
  s = read_surface(p.string());
  EXPECT_DOUBLE_EQ(s.at(0, 0), 1.5);
  EXPECT_DOUBLE_EQ(s.at(1, 0), 2.25);
  EXPECT_DOUBLE_EQ(s.at(1, 1), 5.5);
  EXPECT_DOUBLE_EQ(s.at(2, 1), 0.6);
}

TEST(format_ascii, ThreeColumnMatrixIsNotMistakenForXyz) {
  // Random heights in 3 columns: the first two columns do not form a grid.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1e-6, 1e-6);
  std::string text;
  for (int i = 0; i < 50; ++i) {
    char b[120];
    std::snprintf(b, sizeof b, "%.9g %.9g %.9g\n", u(rng), u(rng), u(rng));
    text += b;
  }
  auto p = temp_path("three.txt");
  spit(p, text);
  Surface s = read_surface(p.string(), spacing(1e-6, 1e-6));
  EXPECT_EQ(s.meta.format, "txt");
  EXPECT_EQ(s.nx, 3u);
  EXPECT_EQ(s.ny, 50u);
  // ...while coordinate-like triples in a .txt are XYZ.
  spit(p, "0 0 5\n1e-6 0 6\n0 1e-6 7\n1e-6 1e-6 8\n0 2e-6 9\n1e-6 2e-6 10\n");
  s = read_surface(p.string());
  EXPECT_EQ(s.meta.format, "xyz");
  EXPECT_EQ(s.nx, 2u);
  EXPECT_EQ(s.ny, 3u);
  EXPECT_DOUBLE_EQ(s.at(1, 2), 10.0);
}

TEST(format_ascii, RejectsMalformedText) {
  auto p = temp_path("bad.txt");
  auto opt = spacing(1e-6, 1e-6);
  spit(p, "1 2 3\n4 5\n");
  std::string e = error_of(p, opt);
  EXPECT_NE(e.find("line 2"), std::string::npos) << e;
  spit(p, "1 2 3\n4 five 6\n");
  e = error_of(p, opt);
  EXPECT_NE(e.find("five"), std::string::npos) << e;
  spit(p, "# only comments\n");
  EXPECT_NE(error_of(p, opt).find("no numeric"), std::string::npos);
  spit(p, "# nx = 3\n1 2\n");
  EXPECT_NE(error_of(p, opt).find("nx"), std::string::npos);
  spit(p, "# units: furlongs\n1 2\n");
  EXPECT_NE(error_of(p, opt).find("furlongs"), std::string::npos);
  spit(p, std::string("1 2\0 3\n", 7));
  EXPECT_NE(error_of(p, opt).find(p.string()), std::string::npos);
  spit(p, "nan nan\nnan nan\n");
  EXPECT_NE(error_of(p, opt).find("no valid"), std::string::npos);
}
