// Gwyddion .gwy reader and writer.
#include <gtest/gtest.h>
#include <unistd.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "microbrdf/error.hpp"
#include "microbrdf/io.hpp"
#include "microbrdf/surface.hpp"

using namespace microbrdf;
namespace fs = std::filesystem;

namespace {

fs::path temp_path(const std::string& file) {
  fs::path dir = fs::temp_directory_path() / ("microbrdf-test-gwy-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir / file;
}

std::vector<std::uint8_t> slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void spit(const fs::path& p, const std::vector<std::uint8_t>& b) {
  std::ofstream out(p, std::ios::binary);
  out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

// A random surface with holes, spacing chosen so that (nx*dx)/nx != dx in floating point.
Surface random_surface(std::size_t nx, std::size_t ny, double dx, double dy, unsigned seed) {
  Surface s(nx, ny, dx, dy);
  s.x0 = -3.3e-6;
  s.y0 = 7.7e-7;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1e-7);
  for (auto& z : s.z) z = g(rng);
  for (std::size_t i = 0; i < s.size(); i += 7) s.invalidate(i);
  s.invalidate(s.size() - 1);
  s.meta.comment = "round trip";
  return s;
}

void expect_bit_equal(const Surface& a, const Surface& b) {
  ASSERT_EQ(a.nx, b.nx);
  ASSERT_EQ(a.ny, b.ny);
  EXPECT_EQ(std::bit_cast<std::uint64_t>(a.dx), std::bit_cast<std::uint64_t>(b.dx));
  EXPECT_EQ(std::bit_cast<std::uint64_t>(a.dy), std::bit_cast<std::uint64_t>(b.dy));
  EXPECT_EQ(std::bit_cast<std::uint64_t>(a.x0), std::bit_cast<std::uint64_t>(b.x0));
  EXPECT_EQ(std::bit_cast<std::uint64_t>(a.y0), std::bit_cast<std::uint64_t>(b.y0));
  std::size_t mismatches = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a.valid[i] != b.valid[i]) ++mismatches;
    if (a.is_valid(i) &&
        std::bit_cast<std::uint64_t>(a.z[i]) != std::bit_cast<std::uint64_t>(b.z[i]))
      ++mismatches;
  }
  EXPECT_EQ(mismatches, 0u);
}

// Minimal GWYP serializer for hand-made (and hostile) test files.
struct Gwy {
  std::vector<std::uint8_t> b;
  void str(const std::string& s) {
    b.insert(b.end(), s.begin(), s.end());
    b.push_back(0);
  }
  void u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void f64(double d) {
    auto u = std::bit_cast<std::uint64_t>(d);
    for (int i = 0; i < 8; ++i) b.push_back(static_cast<std::uint8_t>(u >> (8 * i)));
  }
  std::size_t open(const std::string& type) {
    str(type);
    std::size_t at = b.size();
    u32(0);
    return at;
  }
  void close(std::size_t at) {
    std::uint32_t n = static_cast<std::uint32_t>(b.size() - at - 4);
    for (int i = 0; i < 4; ++i) b[at + i] = static_cast<std::uint8_t>(n >> (8 * i));
  }
  void item_obj(const std::string& name) {
    str(name);
    b.push_back('o');
  }
  void unit(const std::string& key, const std::string& u) {
    item_obj(key);
    auto at = open("GwySIUnit");
    str("unitstr");
    b.push_back('s');
    str(u);
    close(at);
  }
  void field(const std::string& key, int xres, int yres, double xreal, double yreal,
             const std::string& xyu, const std::string& zu, const std::vector<double>& data) {
    item_obj(key);
    auto at = open("GwyDataField");
    str("xres");
    b.push_back('i');
    u32(static_cast<std::uint32_t>(xres));
    str("yres");
    b.push_back('i');
    u32(static_cast<std::uint32_t>(yres));
    str("xreal");
    b.push_back('d');
    f64(xreal);
    str("yreal");
    b.push_back('d');
    f64(yreal);
    unit("si_unit_xy", xyu);
    unit("si_unit_z", zu);
    str("data");
    b.push_back('D');
    u32(static_cast<std::uint32_t>(data.size()));
    for (double d : data) f64(d);
    close(at);
  }
};

std::vector<double> ramp(std::size_t n, double scale) {
  std::vector<double> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = scale * static_cast<double>(i);
  return v;
}

}  // namespace

TEST(format_gwy, ReadsGwyddionFixture) {
  const std::string path = MICROBRDF_TEST_DATA "/test.gwy";
  Surface s = read_surface(path);
  s.check();
  EXPECT_EQ(s.nx, 128u);
  EXPECT_EQ(s.ny, 128u);
  EXPECT_DOUBLE_EQ(s.dx, 1.0);
  EXPECT_DOUBLE_EQ(s.dy, 1.0);
  EXPECT_EQ(s.valid_count(), 128u * 128u);
  double mn = INFINITY, mx = -INFINITY, sum = 0;
  for (double z : s.z) mn = std::min(mn, z), mx = std::max(mx, z), sum += z;
  const double mean = sum / static_cast<double>(s.size());
  double ss = 0;
  for (double z : s.z) ss += (z - mean) * (z - mean);
  const double sq = std::sqrt(ss / static_cast<double>(s.size()));
  EXPECT_NEAR(mn, 0.0, 1e-12);
  EXPECT_NEAR(mx, 0.001, 1e-9);
  EXPECT_NEAR(mean, 0.000515297, 1e-9);
  EXPECT_NEAR(sq, 0.000187711, 1e-9);
  EXPECT_NEAR(s.at(0, 0), 0.000824939, 1e-9);
  EXPECT_EQ(s.meta.format, "gwy");
  EXPECT_EQ(s.meta.comment, "Test");
  EXPECT_EQ(s.meta.source_path, path);
  EXPECT_FALSE(s.meta.get("unit_warning").empty());  // empty unit strings: assumed metres
}

TEST(format_gwy, RoundTripIsBitExact) {
  // Find a spacing near 1.1e-7 for which xreal/xres does not reproduce dx (the case the extra
  // /0/microbrdf/dx item exists for), so the test exercises it.
  const std::size_t nx = 37, ny = 23;
  double dx = 1.1e-7;
  while ((static_cast<double>(nx) * dx) / static_cast<double>(nx) == dx)
    dx = std::nextafter(dx, 1.0);
  const double dy = 1.3e-7;
  Surface s = random_surface(nx, ny, dx, dy, 42);
  auto p = temp_path("rt.gwy");
  write_surface(s, p.string());
  Surface r = read_surface(p.string());
  r.check();
  expect_bit_equal(s, r);
  EXPECT_EQ(r.meta.comment, "round trip");
  EXPECT_EQ(r.meta.z_unit_in_file, "m");
  EXPECT_TRUE(r.meta.get("unit_warning").empty());
  // The file holds no NaN (Gwyddion fields cannot) and has a mask.
  auto bytes = slurp(p);
  std::string text(bytes.begin(), bytes.end());
  EXPECT_NE(text.find("/0/mask"), std::string::npos);
  EXPECT_EQ(text.substr(0, 4), "GWYP");
}

TEST(format_gwy, FullyValidSurfaceHasNoMask) {
  Surface s(5, 4, 2e-6, 2e-6);
  for (std::size_t i = 0; i < s.size(); ++i) s.z[i] = 1e-9 * static_cast<double>(i);
  auto p = temp_path("nomask.gwy");
  write_surface(s, p.string());
  auto bytes = slurp(p);
  std::string text(bytes.begin(), bytes.end());
  EXPECT_EQ(text.find("/0/mask"), std::string::npos);
  Surface r = read_surface(p.string());
  EXPECT_EQ(r.valid_count(), r.size());
  EXPECT_EQ(r.z, s.z);
}

TEST(format_gwy, PicksLowestHeightChannelAndConvertsUnits) {
  Gwy g;
  g.b = {'G', 'W', 'Y', 'P'};
  auto top = g.open("GwyContainer");
  g.field("/12/data", 2, 2, 2.0, 2.0, "m", "m", ramp(4, 1.0));
  g.field("/1/data", 3, 2, 3.0, 2.0, "m", "V", ramp(6, 1.0));  // a voltage channel: skipped
  g.field("/3/data", 4, 2, 8.0, 1.0, "um", "nm", ramp(8, 1.0));
  g.field("/3/mask", 4, 2, 8.0, 1.0, "um", "", {0, 1, 0, 0, 0, 0, 0.7, 0});
  g.str("/3/data/title");
  g.b.push_back('s');
  g.str("Height 3");
  g.str("/3/data/visible");
  g.b.push_back('b');
  g.b.push_back(1);
  g.close(top);
  auto p = temp_path("multi.gwy");
  spit(p, g.b);
  Surface s = read_surface(p.string());
  EXPECT_EQ(s.nx, 4u);
  EXPECT_EQ(s.ny, 2u);
  EXPECT_DOUBLE_EQ(s.dx, 2e-6);
  EXPECT_DOUBLE_EQ(s.dy, 0.5e-6);
  EXPECT_DOUBLE_EQ(s.z[2], 2e-9);
  EXPECT_FALSE(s.is_valid(1));
  EXPECT_FALSE(s.is_valid(6));
  EXPECT_EQ(s.valid_count(), 6u);
  EXPECT_EQ(s.meta.comment, "Height 3");
  EXPECT_EQ(s.meta.get("gwy_channel"), "3");
  EXPECT_EQ(s.meta.z_unit_in_file, "nm");
}

TEST(format_gwy, RejectsLegacyAndCorruptFiles) {
  auto p = temp_path("bad.gwy");
  auto expect_file_error = [&](const std::vector<std::uint8_t>& bytes, const std::string& what) {
    spit(p, bytes);
    try {
      read_surface(p.string(), {}, SurfaceFormat::Gwy);
      ADD_FAILURE() << "no error for " << what;
    } catch (const FileError& e) {
      EXPECT_NE(std::string(e.what()).find(p.string()), std::string::npos) << e.what();
    }
  };
  // Legacy Gwyddion 1.x
  spit(p, {'G', 'W', 'Y', 'O', 'x', 0});
  try {
    read_surface(p.string());
    ADD_FAILURE() << "GWYO accepted";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("Gwyddion 1.x"), std::string::npos) << e.what();
  }
  // Every truncation of the fixture.
  auto full = slurp(MICROBRDF_TEST_DATA "/test.gwy");
  for (std::size_t n : {0ul, 3ul, 4ul, 10ul, 20ul, 200ul, 300ul, 70000ul, full.size() - 1000})
    expect_file_error(std::vector<std::uint8_t>(full.begin(), full.begin() + n),
                      "truncation at " + std::to_string(n));
  // Deeply nested objects.
  {
    Gwy g;
    g.b = {'G', 'W', 'Y', 'P'};
    std::vector<std::size_t> at;
    for (int i = 0; i < 100; ++i) {
      at.push_back(g.open("GwyContainer"));
      g.item_obj("/0/x");
    }
    g.b.resize(g.b.size() - 6);  // drop the last item header ("/0/x\0o")
    for (auto it = at.rbegin(); it != at.rend(); ++it) g.close(*it);
    expect_file_error(g.b, "deep nesting");
  }
  // Unknown component type.
  {
    Gwy g;
    g.b = {'G', 'W', 'Y', 'P'};
    auto top = g.open("GwyContainer");
    g.str("/0/odd");
    g.b.push_back('z');
    g.u32(0);
    g.close(top);
    expect_file_error(g.b, "unknown type");
  }
  // Array count far beyond the file.
  {
    Gwy g;
    g.b = {'G', 'W', 'Y', 'P'};
    auto top = g.open("GwyContainer");
    g.str("/0/arr");
    g.b.push_back('D');
    g.u32(0x10000000);
    g.f64(1.0);
    g.close(top);
    expect_file_error(g.b, "huge array");
  }
  // data size != xres*yres
  {
    Gwy g;
    g.b = {'G', 'W', 'Y', 'P'};
    auto top = g.open("GwyContainer");
    g.field("/0/data", 3, 3, 1.0, 1.0, "m", "m", ramp(8, 1.0));
    g.close(top);
    expect_file_error(g.b, "short data");
  }
  // No channel at all.
  {
    Gwy g;
    g.b = {'G', 'W', 'Y', 'P'};
    auto top = g.open("GwyContainer");
    g.close(top);
    expect_file_error(g.b, "empty container");
  }
}
