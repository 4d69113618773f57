// NumPy .npy array codec (see npy.hpp).
#include "core/npy.hpp"

#include <bit>
#include <cctype>
#include <charconv>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string_view>

#include "core/byte_reader.hpp"
#include "microbrdf/error.hpp"

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

NpyArray parse_npy(std::span<const std::uint8_t> data, const std::string& name) {
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
  std::uint64_t nx = 0, ny = 0, nl = 1;
  if (shape.size() == 1) {
    ny = 1;
    nx = shape[0];
  } else if (shape.size() == 2) {
    ny = shape[0];
    nx = shape[1];
  } else if (shape.size() == 3 && !h.fortran) {  // a stack of 2-D arrays, layer after layer
    nl = shape[0];
    ny = shape[1];
    nx = shape[2];
    if (nl == 0 || (ny != 0 && nl > std::numeric_limits<std::uint64_t>::max() / ny))
      r.fail("npy: implausible number of layers in the shape");
  } else {
    r.fail("npy: expected a 1-D or 2-D array (or a C-order stack of 2-D arrays), shape has " +
           std::to_string(shape.size()) + " dimensions");
  }
  const std::size_t data_at = header_at + header_len;
  // The stack's layers lie one after another: as a grid it is (layers x rows) by cols.
  check_grid(r, nx, ny * nl, t.size, data.size() - data_at);

  NpyArray a;
  a.layers = static_cast<std::size_t>(nl);
  a.rows = static_cast<std::size_t>(ny * nl);
  a.cols = static_cast<std::size_t>(nx);
  a.descr = h.descr;
  a.fortran_order = h.fortran;
  a.values.resize(a.rows * a.cols);
  const std::uint8_t* p = data.data() + data_at;
  if (t.kind == 'f' && t.size == 8 && !t.big && !h.fortran &&
      std::endian::native == std::endian::little) {  // the host's own doubles: one copy
    if (!a.values.empty()) std::memcpy(a.values.data(), p, 8 * a.values.size());
    a.rows /= a.layers;
    return a;
  }
  for (std::size_t iy = 0; iy < a.rows; ++iy) {
    for (std::size_t ix = 0; ix < a.cols; ++ix) {
      // C order: element (iy, ix) at iy*nx + ix; Fortran order: at ix*ny + iy.
      const std::size_t k = h.fortran ? ix * a.rows + iy : iy * a.cols + ix;
      a.values[iy * a.cols + ix] = load(p + k * t.size, t);
    }
  }
  a.rows /= a.layers;
  return a;
}

std::string npy_header_dict_f64(std::size_t rows, std::size_t cols, std::size_t layers,
                                bool layer_axis) {
  const std::string lead = layers > 1 || layer_axis ? std::to_string(layers) + ", " : std::string();
  return "{'descr': '<f8', 'fortran_order': False, 'shape': (" + lead + std::to_string(rows) +
         ", " + std::to_string(cols) + "), }";
}

std::vector<std::uint8_t> encode_npy_f64(std::span<const double> values, std::size_t rows,
                                         std::size_t cols, std::size_t layers, bool layer_axis) {
  if (values.size() != layers * rows * cols)
    throw std::invalid_argument("encode_npy_f64: size mismatch");
  std::string header = npy_header_dict_f64(rows, cols, layers, layer_axis);
  // magic(6) + version(2) + length(2) + header + padding + '\n' = multiple of 64
  std::size_t total = 10 + header.size() + 1;
  header.append((64 - total % 64) % 64, ' ');
  header.push_back('\n');
  if (header.size() > 0xFFFF) throw std::length_error("npy header too long");
  std::vector<std::uint8_t> out(10 + header.size() + 8 * values.size());
  const std::uint8_t pre[8] = {0x93, 'N', 'U', 'M', 'P', 'Y', 1, 0};
  std::memcpy(out.data(), pre, 8);
  out[8] = static_cast<std::uint8_t>(header.size() & 0xFF);
  out[9] = static_cast<std::uint8_t>(header.size() >> 8);
  std::memcpy(out.data() + 10, header.data(), header.size());
  std::uint8_t* p = out.data() + 10 + header.size();
  if constexpr (std::endian::native == std::endian::little) {
    // '<f8' is the host's own layout: one copy.
    if (!values.empty()) std::memcpy(p, values.data(), 8 * values.size());
  } else {
    for (double v : values) {
      const auto u = std::bit_cast<std::uint64_t>(v);
      for (int b = 0; b < 8; ++b) *p++ = static_cast<std::uint8_t>(u >> (8 * b));
    }
  }
  return out;
}

}  // namespace microbrdf::detail
