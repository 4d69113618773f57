// NumPy .npy (format versions 1.0, 2.0, 3.0), read + write.
//
// Reader: the header is a Python dict literal {'descr': ..., 'fortran_order': ..., 'shape': ...}.
// Supported dtypes: float32/float64 ('f4', 'f8'), signed 'i1' 'i2' 'i4' 'i8', unsigned 'u1' 'u2'
// 'u4' 'u8', either byte order ('<', '>', '|', '='); values become doubles. Shape (ny, nx) gives
// ny rows of nx samples (row 0 = first row of the array); (n,) is one row; leading axes of
// length 1 are dropped. Fortran-order arrays are transposed into row-major order. Heights are
// metres; spacing comes from the options (the dispatcher reads a JSON sidecar), else 1 m.
// Writer: float64 little-endian, C order, shape (ny, nx), NaN where invalid (version 1.0 header
// padded to a multiple of 64 bytes, as NumPy does).
#include <bit>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/byte_reader.hpp"
#include "microbrdf/error.hpp"
#include "surface/formats.hpp"

namespace microbrdf::detail {
namespace {

struct Header {
  std::string descr;
  bool fortran = false;
  std::vector<std::uint64_t> shape;
  bool has_descr = false, has_fortran = false, has_shape = false;
};

// A tiny parser for the Python literal NumPy writes. Only what the header can hold.
class DictParser {
 public:
  DictParser(std::string_view s, const ByteReader& r) : s_(s), r_(r) {}

  Header parse() {
    Header h;
    ws();
    expect('{');
    while (true) {
      ws();
      if (peek() == '}') break;
      std::string key = str();
      ws();
      expect(':');
      ws();
      if (key == "descr") {
        if (peek() != '\'' && peek() != '"')
          r_.fail("npy: structured or unsupported dtype (descr is not a string)");
        h.descr = str();
        h.has_descr = true;
      } else if (key == "fortran_order") {
        h.fortran = boolean();
        h.has_fortran = true;
      } else if (key == "shape") {
        h.shape = tuple();
        h.has_shape = true;
      } else {
        r_.fail("npy: unexpected header key '" + key.substr(0, 40) + "'");
      }
      ws();
      if (peek() == ',') {
        ++i_;
        continue;
      }
      if (peek() != '}') expect('}');
    }
    ++i_;
    if (!h.has_descr || !h.has_fortran || !h.has_shape)
      r_.fail("npy: header lacks 'descr', 'fortran_order' or 'shape'");
    return h;
  }

 private:
  char peek() const { return i_ < s_.size() ? s_[i_] : '\0'; }
  void ws() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  void expect(char c) {
    if (peek() != c)
      r_.fail(std::string("npy: malformed header: expected '") + c + "' at header byte " +
              std::to_string(i_));
    ++i_;
  }
  std::string str() {
    char q = peek();
    if (q != '\'' && q != '"') r_.fail("npy: malformed header: expected a quoted string");
    ++i_;
    std::size_t start = i_;
    while (i_ < s_.size() && s_[i_] != q) ++i_;
    if (i_ >= s_.size()) r_.fail("npy: malformed header: unterminated string");
    std::string out(s_.substr(start, i_ - start));
    ++i_;
    return out;
  }
  bool boolean() {
    if (s_.substr(i_, 4) == "True") {
      i_ += 4;
      return true;
    }
    if (s_.substr(i_, 5) == "False") {
      i_ += 5;
      return false;
    }
    r_.fail("npy: malformed header: fortran_order is not True/False");
  }
  std::vector<std::uint64_t> tuple() {
    expect('(');
    std::vector<std::uint64_t> dims;
    while (true) {
      ws();
      if (peek() == ')') break;
      std::uint64_t v = 0;
      auto res = std::from_chars(s_.data() + i_, s_.data() + s_.size(), v);
      if (res.ec != std::errc()) r_.fail("npy: malformed header: bad shape dimension");
      i_ = static_cast<std::size_t>(res.ptr - s_.data());
      if (peek() == 'L') ++i_;  // Python 2 long suffix
      dims.push_back(v);
      if (dims.size() > 32) r_.fail("npy: shape has too many dimensions");
      ws();
      if (peek() == ',') {
        ++i_;
        continue;
      }
      if (peek() != ')') r_.fail("npy: malformed header: bad shape tuple");
    }
    ++i_;
    return dims;
  }

  std::string_view s_;
  const ByteReader& r_;
  std::size_t i_ = 0;
};

struct Dtype {
  char kind = 'f';  // f, i, u
  std::size_t size = 8;
  bool big = false;
};

Dtype parse_descr(const ByteReader& r, const std::string& d) {
  Dtype t;
  if (d.size() < 3 || d.size() > 4) r.fail("npy: unsupported dtype '" + d.substr(0, 20) + "'");
  char order = d[0];
  if (order != '<' && order != '>' && order != '|' && order != '=')
    r.fail("npy: unsupported dtype '" + d + "'");
  t.big = order == '>' || (order == '=' && std::endian::native == std::endian::big);
  t.kind = d[1];
  std::size_t n = 0;
  auto res = std::from_chars(d.data() + 2, d.data() + d.size(), n);
  if (res.ec != std::errc() || res.ptr != d.data() + d.size())
    r.fail("npy: unsupported dtype '" + d + "'");
  t.size = n;
  bool ok = (t.kind == 'f' && (n == 4 || n == 8)) ||
            ((t.kind == 'i' || t.kind == 'u') && (n == 1 || n == 2 || n == 4 || n == 8));
  if (!ok)
    r.fail("npy: unsupported dtype '" + d +
           "' (supported: float32/64, int8/16/32/64, uint8/16/32/64)");
  return t;
}

double load(const std::uint8_t* p, const Dtype& t) {
  std::uint64_t u = 0;
  if (t.big) {
    for (std::size_t i = 0; i < t.size; ++i) u = (u << 8) | p[i];
  } else {
    for (std::size_t i = t.size; i-- > 0;) u = (u << 8) | p[i];
  }
  switch (t.kind) {
    case 'f':
      return t.size == 4 ? static_cast<double>(std::bit_cast<float>(static_cast<std::uint32_t>(u)))
                         : std::bit_cast<double>(u);
    case 'i': {
      const unsigned shift = static_cast<unsigned>(64 - 8 * t.size);
      const auto s = static_cast<std::int64_t>(u << shift) >> shift;  // sign-extend
      return static_cast<double>(s);
    }
    default:
      return static_cast<double>(u);
  }
}

}  // namespace

Surface read_npy(Bytes data, const std::string& name, const ReadOptions& options) {
  ByteReader r(data, name);
  static const std::uint8_t kMagic[6] = {0x93, 'N', 'U', 'M', 'P', 'Y'};
  if (data.size() < 8 || std::memcmp(data.data(), kMagic, 6) != 0)
    r.fail("not a NumPy .npy file (no \\x93NUMPY magic)");
  const unsigned major = data[6], minor = data[7];
  std::size_t header_len = 0, header_at = 0;
  if (major == 1) {
    header_len = r.le<std::uint16_t>(8, "npy header length");
    header_at = 10;
  } else if (major == 2 || major == 3) {
    header_len = r.le<std::uint32_t>(8, "npy header length");
    header_at = 12;
  } else {
    r.fail("npy: unsupported format version " + std::to_string(major) + "." +
           std::to_string(minor));
  }
  auto hb = r.bytes(header_at, header_len, "npy header");
  std::string_view hs(reinterpret_cast<const char*>(hb.data()), hb.size());
  Header h = DictParser(hs, r).parse();
  Dtype t = parse_descr(r, h.descr);

  // Drop leading axes of length 1: (1, ny, nx) is a 2-D array.
  std::vector<std::uint64_t> shape = h.shape;
  while (shape.size() > 2 && shape.front() == 1) shape.erase(shape.begin());
  std::uint64_t nx = 0, ny = 0;
  if (shape.size() == 1) {
    ny = 1;
    nx = shape[0];
  } else if (shape.size() == 2) {
    ny = shape[0];
    nx = shape[1];
  } else {
    r.fail("npy: expected a 1-D or 2-D array, shape has " + std::to_string(shape.size()) +
           " dimensions");
  }
  const std::size_t data_at = header_at + header_len;
  check_grid(r, nx, ny, t.size, data.size() - data_at);

  Surface s;
  s.nx = static_cast<std::size_t>(nx);
  s.ny = static_cast<std::size_t>(ny);
  s.dx = options.dx.value_or(1.0);
  s.dy = options.dy ? *options.dy : s.dx;
  s.z.resize(s.nx * s.ny);
  s.valid.assign(s.z.size(), 1);
  const std::uint8_t* p = data.data() + data_at;
  for (std::size_t iy = 0; iy < s.ny; ++iy) {
    for (std::size_t ix = 0; ix < s.nx; ++ix) {
      // C order: element (iy, ix) at iy*nx + ix; Fortran order: at ix*ny + iy.
      const std::size_t k = h.fortran ? ix * s.ny + iy : iy * s.nx + ix;
      s.z[iy * s.nx + ix] = load(p + k * t.size, t);
    }
  }
  s.meta.format = "npy";
  s.meta.z_unit_in_file = std::string("m");
  s.meta.set("npy_dtype", h.descr);
  if (!options.dx) s.meta.set("unit_warning", "no spacing given; 1 m per sample assumed");
  return s;
}

void write_npy(const Surface& s, const std::string& path) {
  std::string header = "{'descr': '<f8', 'fortran_order': False, 'shape': (" +
                       std::to_string(s.ny) + ", " + std::to_string(s.nx) + "), }";
  // magic(6) + version(2) + length(2) + header + padding + '\n' = multiple of 64
  std::size_t total = 10 + header.size() + 1;
  header.append((64 - total % 64) % 64, ' ');
  header.push_back('\n');
  if (header.size() > 0xFFFF) throw FileError(path, "npy header too long");
  std::vector<std::uint8_t> out;
  out.reserve(10 + header.size() + 8 * s.size());
  const std::uint8_t pre[8] = {0x93, 'N', 'U', 'M', 'P', 'Y', 1, 0};
  out.insert(out.end(), pre, pre + 8);
  out.push_back(static_cast<std::uint8_t>(header.size() & 0xFF));
  out.push_back(static_cast<std::uint8_t>(header.size() >> 8));
  out.insert(out.end(), header.begin(), header.end());
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double v = s.is_valid(i) ? s.z[i] : std::numeric_limits<double>::quiet_NaN();
    const auto u = std::bit_cast<std::uint64_t>(v);
    for (int b = 0; b < 8; ++b) out.push_back(static_cast<std::uint8_t>(u >> (8 * b)));
  }
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw FileError(path, std::string("cannot create: ") + std::strerror(errno));
  const bool ok = std::fwrite(out.data(), 1, out.size(), f) == out.size();
  const bool closed = std::fclose(f) == 0;
  if (!ok || !closed) throw FileError(path, "write error (disk full?)");
}

}  // namespace microbrdf::detail
