// NumPy .npy reader and writer (+ the JSON sidecar handled by the dispatcher).
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
  fs::path dir = fs::temp_directory_path() / ("microbrdf-test-npy-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir / file;
}

void spit(const fs::path& p, const std::vector<std::uint8_t>& b) {
  std::ofstream out(p, std::ios::binary);
  out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

// Builds an .npy file: header dict text + raw payload.
std::vector<std::uint8_t> npy(const std::string& dict, const std::vector<std::uint8_t>& payload,
                              int major = 1) {
  std::string h = dict;
  const std::size_t pre = major == 1 ? 10 : 12;
  while ((pre + h.size() + 1) % 64) h.push_back(' ');
  h.push_back('\n');
  std::vector<std::uint8_t> b = {0x93, 'N', 'U', 'M', 'P', 'Y', static_cast<std::uint8_t>(major),
                                 0};
  const std::size_t n = h.size();
  b.push_back(static_cast<std::uint8_t>(n));
  b.push_back(static_cast<std::uint8_t>(n >> 8));
  if (major != 1) {
    b.push_back(static_cast<std::uint8_t>(n >> 16));
    b.push_back(static_cast<std::uint8_t>(n >> 24));
  }
  b.insert(b.end(), h.begin(), h.end());
  b.insert(b.end(), payload.begin(), payload.end());
  return b;
}

template <class T>
std::vector<std::uint8_t> raw(const std::vector<T>& v, bool big = false) {
  std::vector<std::uint8_t> out;
  for (T x : v) {
    std::uint8_t b[sizeof(T)];
    std::memcpy(b, &x, sizeof(T));
    if (big)
      for (std::size_t i = sizeof(T); i-- > 0;) out.push_back(b[i]);
    else
      out.insert(out.end(), b, b + sizeof(T));
  }
  return out;
}

ReadOptions spacing(double d) {
  ReadOptions o;
  o.dx = d;
  o.dy = d;
  return o;
}

}  // namespace

TEST(format_npy, RoundTripWithSidecarIsBitExact) {
  Surface s(29, 17, 1.1e-7, 1.3e-7);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> g(0.0, 3e-8);
  for (auto& z : s.z) z = g(rng);
  for (std::size_t i = 3; i < s.size(); i += 11) s.invalidate(i);
  auto p = temp_path("rt.npy");
  write_surface(s, p.string());
  ASSERT_TRUE(fs::exists(temp_path("rt.json")));  // the sidecar holds the spacing
  Surface r = read_surface(p.string());
  r.check();
  ASSERT_EQ(r.nx, s.nx);
  ASSERT_EQ(r.ny, s.ny);
  EXPECT_EQ(std::bit_cast<std::uint64_t>(r.dx), std::bit_cast<std::uint64_t>(s.dx));
  EXPECT_EQ(std::bit_cast<std::uint64_t>(r.dy), std::bit_cast<std::uint64_t>(s.dy));
  EXPECT_EQ(r.valid, s.valid);
  std::size_t differ = 0;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (s.is_valid(i) &&
        std::bit_cast<std::uint64_t>(r.z[i]) != std::bit_cast<std::uint64_t>(s.z[i]))
      ++differ;
  EXPECT_EQ(differ, 0u);
  EXPECT_EQ(r.meta.format, "npy");

  // The file itself is a plain float64 C-order array of shape (ny, nx).
  std::ifstream in(p, std::ios::binary);
  std::string head(128, '\0');
  in.read(head.data(), 128);
  EXPECT_NE(head.find("'descr': '<f8'"), std::string::npos);
  EXPECT_NE(head.find("'shape': (17, 29)"), std::string::npos);
  EXPECT_EQ(fs::file_size(p) % 64, (17u * 29u * 8u) % 64);  // header padded to 64 bytes
}

TEST(format_npy, NeedsSpacingWithoutSidecar) {
  auto p = temp_path("nosidecar.npy");
  spit(p, npy("{'descr': '<f8', 'fortran_order': False, 'shape': (2, 2), }",
              raw<double>({1, 2, 3, 4})));
  fs::remove(temp_path("nosidecar.json"));
  EXPECT_THROW(read_surface(p.string()), FileError);
  Surface s = read_surface(p.string(), spacing(5e-7));
  EXPECT_DOUBLE_EQ(s.dx, 5e-7);
  EXPECT_DOUBLE_EQ(s.at(1, 0), 2.0);
  EXPECT_DOUBLE_EQ(s.at(0, 1), 3.0);
  // In memory (what the fuzzer calls) the spacing defaults to 1 m.
  std::ifstream in(p, std::ios::binary);
  std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in), {}};
  Surface m = read_surface_bytes(bytes, SurfaceFormat::Npy, "mem");
  EXPECT_DOUBLE_EQ(m.dx, 1.0);
}

TEST(format_npy, DtypesOrdersAndShapes) {
  auto p = temp_path("dtypes.npy");
  auto read = [&](const std::vector<std::uint8_t>& b) {
    spit(p, b);
    return read_surface(p.string(), spacing(1e-6));
  };
  // float32 little endian, 2 x 3
  Surface s = read(npy("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }",
                       raw<float>({1.5f, 2.5f, NAN, 4, 5, 6})));
  EXPECT_EQ(s.nx, 3u);
  EXPECT_EQ(s.ny, 2u);
  EXPECT_DOUBLE_EQ(s.at(1, 0), 2.5);
  EXPECT_FALSE(s.is_valid(2));
  EXPECT_DOUBLE_EQ(s.at(2, 1), 6.0);
  // float64 big endian
  s = read(npy("{'descr': '>f8', 'fortran_order': False, 'shape': (1, 2), }",
               raw<double>({0.125, -3e-9}, true)));
  EXPECT_DOUBLE_EQ(s.z[1], -3e-9);
  // big-endian float32
  s = read(npy("{'descr': '>f4', 'fortran_order': False, 'shape': (2,), }",
               raw<float>({7.0f, -1.0f}, true)));
  EXPECT_EQ(s.ny, 1u);
  EXPECT_DOUBLE_EQ(s.z[1], -1.0);
  // int16, uint16, int32, uint8
  s = read(npy("{'descr': '<i2', 'fortran_order': False, 'shape': (2, 2), }",
               raw<std::int16_t>({-32768, -1, 0, 32767})));
  EXPECT_DOUBLE_EQ(s.z[0], -32768.0);
  EXPECT_DOUBLE_EQ(s.z[1], -1.0);
  s = read(npy("{'descr': '<u2', 'fortran_order': False, 'shape': (2, 2), }",
               raw<std::uint16_t>({65535, 1, 2, 3})));
  EXPECT_DOUBLE_EQ(s.z[0], 65535.0);
  s = read(npy("{'descr': '<i4', 'fortran_order': False, 'shape': (1, 2), }",
               raw<std::int32_t>({-5, 2147483647})));
  EXPECT_DOUBLE_EQ(s.z[0], -5.0);
  EXPECT_DOUBLE_EQ(s.z[1], 2147483647.0);
  s = read(npy("{'descr': '|u1', 'fortran_order': False, 'shape': (1, 3), }",
               raw<std::uint8_t>({0, 128, 255})));
  EXPECT_DOUBLE_EQ(s.z[2], 255.0);
  // Fortran order: shape (2, 3) stored column by column
  s = read(npy("{'descr': '<f8', 'fortran_order': True, 'shape': (2, 3), }",
               raw<double>({11, 21, 12, 22, 13, 23})));
  EXPECT_EQ(s.nx, 3u);
  EXPECT_EQ(s.ny, 2u);
  EXPECT_DOUBLE_EQ(s.at(0, 0), 11);
  EXPECT_DOUBLE_EQ(s.at(2, 0), 13);
  EXPECT_DOUBLE_EQ(s.at(0, 1), 21);
  EXPECT_DOUBLE_EQ(s.at(2, 1), 23);
  // Version 2.0 and 3.0 headers, key order irrelevant, (1, ny, nx) accepted
  s = read(npy("{'shape': (1, 2, 2), 'fortran_order': False, 'descr': '<f8'}",
               raw<double>({1, 2, 3, 4}), 2));
  EXPECT_EQ(s.nx, 2u);
  EXPECT_EQ(s.ny, 2u);
  s = read(npy("{\"descr\": \"<f8\", \"fortran_order\": False, \"shape\": (1, 1)}",
               raw<double>({9}), 3));
  EXPECT_DOUBLE_EQ(s.z[0], 9.0);
}

TEST(format_npy, RejectsCorruptFiles) {
  auto p = temp_path("bad.npy");
  auto expect_error = [&](const std::vector<std::uint8_t>& b, const std::string& what) {
    spit(p, b);
    try {
      read_surface(p.string(), spacing(1e-6), SurfaceFormat::Npy);
      ADD_FAILURE() << "no error for " << what;
    } catch (const FileError& e) {
      EXPECT_NE(std::string(e.what()).find(p.string()), std::string::npos) << e.what();
    }
  };
  const std::string ok = "{'descr': '<f8', 'fortran_order': False, 'shape': (2, 2), }";
  auto good = npy(ok, raw<double>({1, 2, 3, 4}));
  for (std::size_t n : {0ul, 5ul, 9ul, 40ul, good.size() - 1})
    expect_error(std::vector<std::uint8_t>(good.begin(), good.begin() + n), "truncated");
  expect_error(npy("{'descr': '<c16', 'fortran_order': False, 'shape': (1, 1), }",
                   std::vector<std::uint8_t>(16, 0)),
               "complex dtype");
  expect_error(npy("{'descr': [('a', '<f8')], 'fortran_order': False, 'shape': (1,), }",
                   std::vector<std::uint8_t>(8, 0)),
               "structured dtype");
  expect_error(npy("{'descr': '<f8', 'fortran_order': False, 'shape': (4294967296, "
                   "4294967296), }",
                   raw<double>({1})),
               "absurd shape");
  expect_error(npy("{'descr': '<f8', 'fortran_order': False, 'shape': (99999999999999999999,), }",
                   raw<double>({1})),
               "overflowing dimension");
  expect_error(npy("{'descr': '<f8', 'fortran_order': False, 'shape': (2, 2, 2), }",
                   raw<double>({1, 2, 3, 4, 5, 6, 7, 8})),
               "3-D");
  expect_error(npy("{'descr': '<f8', 'fortran_order': Maybe, 'shape': (1,), }", raw<double>({1})),
               "bad bool");
  expect_error(npy("{'descr': '<f8', 'shape': (1,), }", raw<double>({1})), "missing key");
  auto v9 = good;
  v9[6] = 9;
  expect_error(v9, "version 9");
}
