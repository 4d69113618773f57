// RGL tensor container: parser and writer (include/microbrdf/tensor_file.hpp).
#include "microbrdf/tensor_file.hpp"

#include <cstring>
#include <limits>

#include "core/byte_reader.hpp"
#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/io.hpp"

namespace microbrdf {
namespace {

constexpr char kMagic[12] = "tensor_file";  // 11 characters and the NUL
constexpr std::size_t kPreamble = 12 + 2 + 4;
// Smallest possible field header: name_length, ndim, dtype, offset (empty name, ndim 0).
constexpr std::size_t kMinFieldHeader = 2 + 2 + 1 + 8;

void put_bytes(std::vector<std::uint8_t>& out, const void* p, std::size_t n) {
  // resize + memcpy (vector::insert of a raw range trips a GCC 12 -Wstringop-overflow false
  // positive).
  const std::size_t at = out.size();
  out.resize(at + n);
  if (n) std::memcpy(out.data() + at, p, n);
}
template <class T>
void put_le(std::vector<std::uint8_t>& out, T v) {
  static_assert(std::endian::native == std::endian::little, "little-endian host assumed");
  put_bytes(out, &v, sizeof v);
}

}  // namespace

std::size_t tensor_dtype_size(TensorDtype t) {
  switch (t) {
    case TensorDtype::UInt8:
    case TensorDtype::Int8:
      return 1;
    case TensorDtype::UInt16:
    case TensorDtype::Int16:
    case TensorDtype::Float16:
      return 2;
    case TensorDtype::UInt32:
    case TensorDtype::Int32:
    case TensorDtype::Float32:
      return 4;
    case TensorDtype::UInt64:
    case TensorDtype::Int64:
    case TensorDtype::Float64:
      return 8;
  }
  return 0;
}

std::uint64_t TensorField::count() const {
  std::uint64_t n = 1;
  for (auto s : shape) n *= s;
  return n;
}

TensorField TensorField::float32(std::string name, std::vector<std::uint64_t> shape,
                                 std::span<const double> values) {
  std::vector<float> f(values.begin(), values.end());
  return float32(std::move(name), std::move(shape), std::span<const float>(f));
}

TensorField TensorField::float32(std::string name, std::vector<std::uint64_t> shape,
                                 std::span<const float> values) {
  TensorField t;
  t.name = std::move(name);
  t.dtype = TensorDtype::Float32;
  t.shape = std::move(shape);
  if (t.count() != values.size())
    throw std::invalid_argument("TensorField::float32: shape does not match the value count");
  t.data.resize(values.size() * 4);
  std::memcpy(t.data.data(), values.data(), t.data.size());
  return t;
}

TensorField TensorField::uint8(std::string name, std::vector<std::uint64_t> shape,
                               std::span<const std::uint8_t> values) {
  TensorField t;
  t.name = std::move(name);
  t.dtype = TensorDtype::UInt8;
  t.shape = std::move(shape);
  if (t.count() != values.size())
    throw std::invalid_argument("TensorField::uint8: shape does not match the value count");
  t.data.assign(values.begin(), values.end());
  return t;
}

std::vector<float> TensorField::as_float32(const std::string& path) const {
  if (dtype != TensorDtype::Float32)
    throw FileError(path, "field \"" + name + "\" is not float32 (dtype code " +
                              std::to_string(static_cast<int>(dtype)) + ")");
  std::vector<float> v(data.size() / 4);
  std::memcpy(v.data(), data.data(), v.size() * 4);
  return v;
}

const TensorField* TensorFile::find(const std::string& name) const {
  for (const auto& f : fields)
    if (f.name == name) return &f;
  return nullptr;
}

const TensorField& TensorFile::field(const std::string& name, const std::string& path) const {
  const TensorField* f = find(name);
  if (!f) throw FileError(path, "no field \"" + name + "\" in the tensor file");
  return *f;
}

TensorFile parse_tensor_file(std::span<const std::uint8_t> bytes, const std::string& name) {
  detail::ByteReader r(bytes, name);
  if (bytes.size() < kPreamble) r.fail("not a tensor file: too short for the header");
  if (std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    r.fail("not a tensor file: the header does not start with \"tensor_file\"");
  const std::uint8_t major = bytes[12], minor = bytes[13];
  if (major != 1 || minor != 0)
    r.fail("unsupported tensor file version " + std::to_string(major) + "." +
           std::to_string(minor) + " (1.0 expected)");
  const std::uint32_t n_fields = r.le<std::uint32_t>(14, "field count");
  if (n_fields > (bytes.size() - kPreamble) / kMinFieldHeader)
    r.fail("corrupt header: " + std::to_string(n_fields) + " fields cannot fit in " +
           std::to_string(bytes.size()) + " bytes");
  detail::ByteCursor c(r, kPreamble);
  TensorFile file;
  file.fields.reserve(n_fields);
  for (std::uint32_t i = 0; i < n_fields; ++i) {
    TensorField f;
    const std::uint16_t len = c.le<std::uint16_t>("field name length");
    const auto nb = c.bytes(len, "field name");
    f.name.assign(reinterpret_cast<const char*>(nb.data()), nb.size());
    const std::uint16_t ndim = c.le<std::uint16_t>("field ndim");
    const std::uint8_t dt = c.le<std::uint8_t>("field dtype");
    const std::uint64_t offset = c.le<std::uint64_t>("field offset");
    if (dt < 1 || dt > 11)
      r.fail("field \"" + f.name + "\": unknown dtype code " + std::to_string(dt));
    f.dtype = static_cast<TensorDtype>(dt);
    if (std::uint64_t(ndim) * 8 > c.remaining())
      r.fail("truncated or corrupt: field \"" + f.name + "\" declares " + std::to_string(ndim) +
             " dimensions");
    f.shape.resize(ndim);
    std::uint64_t count = 1;
    const std::uint64_t esize = tensor_dtype_size(f.dtype);
    for (auto& s : f.shape) {
      s = c.le<std::uint64_t>("field shape");
      // count * s * esize must stay within the file: checked before it can overflow.
      if (s != 0 && count > bytes.size() / esize / s)
        r.fail("corrupt header: field \"" + f.name + "\" is larger than the file");
      count *= s;
    }
    const std::uint64_t nbytes = count * esize;
    r.require(offset, nbytes, "tensor field data");
    const auto d = r.bytes(offset, nbytes, "tensor field data");
    f.data.assign(d.begin(), d.end());
    for (const auto& g : file.fields)
      if (g.name == f.name) r.fail("field \"" + f.name + "\" appears twice");
    file.fields.push_back(std::move(f));
  }
  return file;
}

TensorFile read_tensor_file(const std::string& path) {
  const auto bytes = read_file_bytes(path, std::uint64_t{1} << 32);
  return parse_tensor_file(bytes, path);
}

std::vector<std::uint8_t> encode_tensor_file(const TensorFile& file) {
  std::vector<std::uint8_t> out;
  put_bytes(out, kMagic, sizeof kMagic);
  out.push_back(1);
  out.push_back(0);
  put_le<std::uint32_t>(out, static_cast<std::uint32_t>(file.fields.size()));
  std::size_t header = out.size();
  for (const auto& f : file.fields) header += 2 + f.name.size() + 2 + 1 + 8 + 8 * f.shape.size();
  auto align8 = [](std::uint64_t x) { return (x + 7) / 8 * 8; };
  std::uint64_t offset = align8(header);
  std::vector<std::uint64_t> offsets;
  for (const auto& f : file.fields) {
    if (f.name.size() > std::numeric_limits<std::uint16_t>::max() ||
        f.shape.size() > std::numeric_limits<std::uint16_t>::max() ||
        f.data.size() != f.count() * tensor_dtype_size(f.dtype))
      throw std::invalid_argument("encode_tensor_file: malformed field \"" + f.name + "\"");
    offsets.push_back(offset);
    offset = align8(offset + f.data.size());
  }
  for (std::size_t i = 0; i < file.fields.size(); ++i) {
    const auto& f = file.fields[i];
    put_le<std::uint16_t>(out, static_cast<std::uint16_t>(f.name.size()));
    put_bytes(out, f.name.data(), f.name.size());
    put_le<std::uint16_t>(out, static_cast<std::uint16_t>(f.shape.size()));
    out.push_back(static_cast<std::uint8_t>(f.dtype));
    put_le<std::uint64_t>(out, offsets[i]);
    for (auto s : f.shape) put_le<std::uint64_t>(out, s);
  }
  for (std::size_t i = 0; i < file.fields.size(); ++i) {
    out.resize(offsets[i], 0);
    put_bytes(out, file.fields[i].data.data(), file.fields[i].data.size());
  }
  out.resize(align8(out.size()), 0);
  return out;
}

void write_tensor_file(const TensorFile& file, const std::string& path) {
  const auto bytes = encode_tensor_file(file);
  write_file_atomic(path, bytes);
}

}  // namespace microbrdf
