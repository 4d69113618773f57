#pragma once
// The tensor container of the RGL material database (Dupuy & Jakob 2018), read by Mitsuba 3's
// `measured` plugin and pbrt-v4's MeasuredBxDF. Layout (little-endian), docs/formats.md:
//
//   char[12] "tensor_file\0" | uint8 version[2] = {1, 0} | uint32 field_count
//   per field: uint16 name_length | name bytes | uint16 ndim | uint8 dtype | uint64 offset
//              | uint64 shape[ndim]
//   data blocks at their (absolute) offsets, C order; the writer aligns each block to 8 bytes.
//
// dtype codes are Mitsuba's Struct::Type: 1 uint8, 2 int8, 3 uint16, 4 int16, 5 uint32,
// 6 int32, 7 uint64, 8 int64, 9 float16, 10 float32, 11 float64.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace microbrdf {

enum class TensorDtype : std::uint8_t {
  UInt8 = 1,
  Int8,
  UInt16,
  Int16,
  UInt32,
  Int32,
  UInt64,
  Int64,
  Float16,
  Float32,
  Float64
};
/// Bytes per element of a dtype.
std::size_t tensor_dtype_size(TensorDtype t);

struct TensorField {
  std::string name;
  TensorDtype dtype = TensorDtype::Float32;
  std::vector<std::uint64_t> shape;
  std::vector<std::uint8_t> data;  ///< raw little-endian elements, C order
  /// Number of elements (product of the shape; 1 for ndim = 0).
  std::uint64_t count() const;
  /// A float32 field from values (narrowed).
  static TensorField float32(std::string name, std::vector<std::uint64_t> shape,
                             std::span<const double> values);
  static TensorField float32(std::string name, std::vector<std::uint64_t> shape,
                             std::span<const float> values);
  static TensorField uint8(std::string name, std::vector<std::uint64_t> shape,
                           std::span<const std::uint8_t> values);
  /// The elements of a float32 field. Throws FileError(path, ...) for another dtype.
  std::vector<float> as_float32(const std::string& path) const;
};

struct TensorFile {
  std::vector<TensorField> fields;
  /// The field called `name`, or nullptr.
  const TensorField* find(const std::string& name) const;
  /// The field called `name`; throws FileError(path, "no field ...") when it is missing.
  const TensorField& field(const std::string& name, const std::string& path) const;
};

/// Parses a tensor file held in memory. Every size and offset is checked against the buffer
/// before anything is allocated or read, so a hostile header cannot force an allocation beyond
/// what the file holds. Throws FileError(name, ...).
TensorFile parse_tensor_file(std::span<const std::uint8_t> bytes, const std::string& name);
/// Reads `path` (at most 4 GiB). Throws FileError.
TensorFile read_tensor_file(const std::string& path);
/// The file's bytes: header, then each field's block at an 8-byte aligned offset.
std::vector<std::uint8_t> encode_tensor_file(const TensorFile& file);
/// Writes atomically (temporary + rename). Throws FileError.
void write_tensor_file(const TensorFile& file, const std::string& path);

}  // namespace microbrdf
