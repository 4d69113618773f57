// NumPy .npy (format versions 1.0, 2.0, 3.0), read + write.
//
// Reader: the header is a Python dict literal {'descr': ..., 'fortran_order': ..., 'shape': ...}.
// Supported dtypes: float32/float64 ('f4', 'f8'), signed 'i1' 'i2' 'i4' 'i8', unsigned 'u1' 'u2'
// 'u4' 'u8', either byte order ('<', '>', '|', '='); values become doubles. Shape (ny, nx) gives
// ny rows of nx samples (row 0 = first row of the array); (n,) is one row; leading axes of
// length 1 are dropped. Fortran-order arrays are transposed into row-major order. Heights are
// metres; spacing comes from the options (the dispatcher reads a JSON sidecar), else 1 m.
// Writer: float64 little-endian, C order, shape (ny, nx), NaN where invalid (version 1.0 header
// padded to a multiple of 64 bytes, as NumPy does). The array codec itself is core/npy.cpp.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/npy.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/file_size_limit.hpp"
#include "surface/formats.hpp"

namespace microbrdf::detail {

Surface read_npy(Bytes data, const std::string& name, const ReadOptions& options) {
  NpyArray a = parse_npy(data, name);
  if (a.layers > 1)
    throw FileError(name, "holds a stack of " + std::to_string(a.layers) +
                              " arrays (a 3-D shape), not one height map");
  Surface s;
  s.nx = a.cols;
  s.ny = a.rows;
  s.dx = options.dx.value_or(1.0);
  s.dy = options.dy ? *options.dy : s.dx;
  s.z = std::move(a.values);
  s.valid.assign(s.z.size(), 1);
  s.meta.format = "npy";
  s.meta.z_unit_in_file = std::string("m");
  s.meta.set("npy_dtype", a.descr);
  if (!options.dx) s.meta.set("unit_warning", "no spacing given; 1 m per sample assumed");
  return s;
}

void write_npy(const Surface& s, const std::string& path) {
  std::vector<double> z(s.size());
  for (std::size_t i = 0; i < s.size(); ++i)
    z[i] = s.is_valid(i) ? s.z[i] : std::numeric_limits<double>::quiet_NaN();
  std::vector<std::uint8_t> out;
  try {
    out = encode_npy_f64(z, s.ny, s.nx);
  } catch (const std::length_error&) {
    throw FileError(path, "npy header too long");
  }
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw FileError(path, std::string("cannot create: ") + std::strerror(errno));
  const bool ok = std::fwrite(out.data(), 1, out.size(), f) == out.size();
  int err = ok ? 0 : errno;
  const bool closed = std::fclose(f) == 0;
  if (!closed && ok) err = errno;
  if (!ok || !closed) throw FileError(path, write_failure_problem(err));
}

}  // namespace microbrdf::detail
