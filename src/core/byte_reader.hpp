#pragma once
// Bounds-checked reads of little- and big-endian numbers from a byte buffer. Every read past the
// end throws FileError("<name>: truncated ..."), so binary readers never touch memory the file
// does not have, whatever its header claims.

#include <bit>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>

#include "microbrdf/error.hpp"

namespace microbrdf::detail {

class ByteReader {
 public:
  ByteReader(std::span<const std::uint8_t> data, std::string name)
      : data_(data), name_(std::move(name)) {}

  std::size_t size() const { return data_.size(); }
  const std::string& name() const { return name_; }
  std::span<const std::uint8_t> data() const { return data_; }

  [[noreturn]] void fail(const std::string& problem) const { throw FileError(name_, problem); }

  /// Throws unless [offset, offset+count) lies inside the buffer. `what` names the field.
  void require(std::size_t offset, std::size_t count, const char* what) const {
    if (offset > data_.size() || count > data_.size() - offset) {
      fail("truncated or corrupt: " + std::string(what) + " needs " + std::to_string(count) +
           " bytes at offset " + std::to_string(offset) + ", but the file has " +
           std::to_string(data_.size()) + " bytes");
    }
  }

  std::span<const std::uint8_t> bytes(std::size_t offset, std::size_t count,
                                      const char* what = "data") const {
    require(offset, count, what);
    return data_.subspan(offset, count);
  }

  template <class T>
  T le(std::size_t offset, const char* what = "header field") const {
    return load<T>(offset, what, std::endian::little);
  }
  template <class T>
  T be(std::size_t offset, const char* what = "header field") const {
    return load<T>(offset, what, std::endian::big);
  }

  /// A fixed-width text field, cut at the first NUL, trailing spaces removed.
  std::string text(std::size_t offset, std::size_t len, const char* what = "text field") const {
    auto b = bytes(offset, len, what);
    std::size_t n = 0;
    while (n < b.size() && b[n] != 0) ++n;
    while (n > 0 && (b[n - 1] == ' ' || b[n - 1] == '\t')) --n;
    return std::string(reinterpret_cast<const char*>(b.data()), n);
  }

 private:
  template <class T>
  T load(std::size_t offset, const char* what, std::endian order) const {
    static_assert(std::is_trivially_copyable_v<T>);
    require(offset, sizeof(T), what);
    std::uint8_t buf[sizeof(T)];
    std::memcpy(buf, data_.data() + offset, sizeof(T));
    if (order != std::endian::native) {
      for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(buf[i], buf[sizeof(T) - 1 - i]);
    }
    T v;
    std::memcpy(&v, buf, sizeof(T));
    return v;
  }

  std::span<const std::uint8_t> data_;
  std::string name_;
};

/// Sequential reader on top of ByteReader (for serialised formats such as .gwy).
class ByteCursor {
 public:
  ByteCursor(const ByteReader& r, std::size_t pos = 0, std::size_t end = SIZE_MAX)
      : r_(r), pos_(pos), end_(end < r.size() ? end : r.size()) {}
  std::size_t pos() const { return pos_; }
  std::size_t end() const { return end_; }
  std::size_t remaining() const { return end_ > pos_ ? end_ - pos_ : 0; }
  void skip(std::size_t n, const char* what = "data") {
    need(n, what);
    pos_ += n;
  }
  template <class T>
  T le(const char* what = "field") {
    need(sizeof(T), what);
    T v = r_.le<T>(pos_, what);
    pos_ += sizeof(T);
    return v;
  }
  template <class T>
  T be(const char* what = "field") {
    need(sizeof(T), what);
    T v = r_.be<T>(pos_, what);
    pos_ += sizeof(T);
    return v;
  }
  /// A NUL-terminated string; fails if no NUL within `max_len` bytes or before `end`.
  std::string cstring(std::size_t max_len = 4096, const char* what = "string") {
    std::size_t n = 0;
    auto d = r_.data();
    while (true) {
      if (pos_ + n >= end_) r_.fail(std::string("truncated or corrupt: unterminated ") + what);
      if (d[pos_ + n] == 0) break;
      if (++n > max_len)
        r_.fail(std::string("corrupt: ") + what + " longer than " + std::to_string(max_len) +
                " bytes");
    }
    std::string s(reinterpret_cast<const char*>(d.data() + pos_), n);
    pos_ += n + 1;
    return s;
  }
  std::span<const std::uint8_t> bytes(std::size_t n, const char* what = "data") {
    need(n, what);
    auto b = r_.bytes(pos_, n, what);
    pos_ += n;
    return b;
  }
  const ByteReader& reader() const { return r_; }

 private:
  void need(std::size_t n, const char* what) const {
    if (n > remaining()) {
      r_.fail(std::string("truncated or corrupt: ") + what + " needs " + std::to_string(n) +
              " bytes at offset " + std::to_string(pos_) + ", only " + std::to_string(remaining()) +
              " remain");
    }
  }
  const ByteReader& r_;
  std::size_t pos_;
  std::size_t end_;
};

/// Checks that a grid of nx*ny samples of `bytes_per_sample` fits in `available` bytes and in
/// a sane maximum (2^31 samples); throws FileError otherwise. Guards every header-driven
/// allocation.
inline void check_grid(const ByteReader& r, std::uint64_t nx, std::uint64_t ny,
                       std::uint64_t bytes_per_sample, std::uint64_t available) {
  if (nx == 0 || ny == 0)
    r.fail("empty grid (" + std::to_string(nx) + " x " + std::to_string(ny) + ")");
  constexpr std::uint64_t kMaxSamples = std::uint64_t{1} << 31;
  if (nx > kMaxSamples || ny > kMaxSamples || nx * ny > kMaxSamples) {
    r.fail("corrupt header: grid " + std::to_string(nx) + " x " + std::to_string(ny) +
           " is absurdly large");
  }
  if (bytes_per_sample != 0 && nx * ny * bytes_per_sample > available) {
    r.fail("truncated or corrupt: header says " + std::to_string(nx) + " x " + std::to_string(ny) +
           " samples (" + std::to_string(nx * ny * bytes_per_sample) + " bytes) but only " +
           std::to_string(available) + " bytes of data follow");
  }
}

}  // namespace microbrdf::detail
