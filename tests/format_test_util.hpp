#pragma once
// Helpers shared by the file-format tests: statistics of the valid samples (for the reference
// values in tests/data/README.md), a per-test temporary directory, byte patching for hostile
// headers, and the "FileError naming the file" check.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "microbrdf/error.hpp"
#include "microbrdf/io.hpp"

namespace microbrdf::test {

namespace fs = std::filesystem;

struct Stats {
  std::size_t invalid = 0;
  double min = INFINITY, max = -INFINITY, mean = 0, sq = 0;
};

inline Stats stats(const Surface& s) {
  Stats st;
  double sum = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (!s.is_valid(i)) {
      ++st.invalid;
      continue;
    }
    st.min = std::min(st.min, s.z[i]);
    st.max = std::max(st.max, s.z[i]);
    sum += s.z[i];
    ++n;
  }
  st.mean = sum / static_cast<double>(n);
  double ss = 0;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (s.is_valid(i)) ss += (s.z[i] - st.mean) * (s.z[i] - st.mean);
  st.sq = std::sqrt(ss / static_cast<double>(n));
  return st;
}

inline std::vector<std::uint8_t> load(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class TempDir {
 public:
  TempDir() {
    path_ = fs::temp_directory_path() /
            ("microbrdf-test-" + std::to_string(::getpid()) + "-" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  std::string write(const std::string& name, const std::vector<std::uint8_t>& bytes) const {
    std::string p = (path_ / name).string();
    std::ofstream out(p, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
    return p;
  }

 private:
  fs::path path_;
};

inline void put_le16(std::vector<std::uint8_t>& b, std::size_t off, std::uint16_t v) {
  b[off] = static_cast<std::uint8_t>(v);
  b[off + 1] = static_cast<std::uint8_t>(v >> 8);
}

inline void put_le32(std::vector<std::uint8_t>& b, std::size_t off, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b[off + i] = static_cast<std::uint8_t>(v >> (8 * i));
}

inline void expect_file_error(const std::string& path, const std::string& needle = "",
                              const ReadOptions& opt = ReadOptions()) {
  try {
    read_surface(path, opt);
    ADD_FAILURE() << "no error for " << path;
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    if (!needle.empty()) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  }
}

inline void put_be16(std::vector<std::uint8_t>& b, std::size_t off, std::uint16_t v) {
  b[off] = static_cast<std::uint8_t>(v >> 8);
  b[off + 1] = static_cast<std::uint8_t>(v);
}

inline void put_be32(std::vector<std::uint8_t>& b, std::size_t off, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b[off + i] = static_cast<std::uint8_t>(v >> (24 - 8 * i));
}

inline void put_f32(std::vector<std::uint8_t>& b, std::size_t off, float f) {
  std::uint32_t bits;
  std::memcpy(&bits, &f, 4);
  put_le32(b, off, bits);
}

}  // namespace microbrdf::test
