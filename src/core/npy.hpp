#pragma once
// NumPy .npy array codec shared by the height-map reader/writer (surface/format_npy.cpp) and
// the NDF tables (ndf/ndf_io.cpp). Array level only: no Surface, no sidecars.
//
// Reader: format versions 1.0, 2.0, 3.0; the header is the Python dict literal
// {'descr': ..., 'fortran_order': ..., 'shape': ...}. dtypes float32/float64 ('f4', 'f8'),
// signed 'i1' 'i2' 'i4' 'i8', unsigned 'u1' 'u2' 'u4' 'u8', either byte order ('<', '>', '|',
// '='); values become doubles. Shape (rows, cols); (n,) is one row; leading axes of length 1
// are dropped. Fortran-order arrays are transposed into row-major order. Shape (layers, rows,
// cols) in C order is a stack of equal 2-D arrays (a stack of NDF tables); readers that want
// one 2-D array refuse layers > 1.
// Writer: float64 little-endian, C order, version 1.0 header padded so that the data starts
// at a multiple of 64 bytes, as NumPy does.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace microbrdf::detail {

struct NpyArray {
  std::size_t layers = 1, rows = 0, cols = 0;
  std::vector<double> values;  ///< row-major, layers * rows * cols (layer after layer)
  std::string descr;           ///< dtype as written in the header, e.g. "<f8"
  bool fortran_order = false;  ///< as stored (values are row-major regardless)
};

/// Parses a whole .npy file held in memory. Throws FileError(name, ...) on anything malformed,
/// truncated or unsupported.
NpyArray parse_npy(std::span<const std::uint8_t> data, const std::string& name);

/// The header dict NumPy would write for a C-order float64 array of shape (rows, cols), or
/// (layers, rows, cols) when layers > 1 or `layer_axis` (an image of one row stays 3-D).
std::string npy_header_dict_f64(std::size_t rows, std::size_t cols, std::size_t layers = 1,
                                bool layer_axis = false);

/// Serialises `values` (row-major, layers * rows * cols) as a float64 C-order .npy file of shape
/// (rows, cols), or (layers, rows, cols) when layers > 1 or `layer_axis`.
/// Throws std::length_error if the header would not fit a version 1.0 file.
std::vector<std::uint8_t> encode_npy_f64(std::span<const double> values, std::size_t rows,
                                         std::size_t cols, std::size_t layers = 1,
                                         bool layer_axis = false);

}  // namespace microbrdf::detail
