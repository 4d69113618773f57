#pragma once
// One reader (and writer where the format allows) per file format. Readers parse bytes held in
// memory so the same code serves files and fuzz targets; `name` is the file's path for error
// messages. Every reader returns heights in metres, keeps the file's row order, marks invalid
// points (NaN + mask) and fills SurfaceMetadata as far as the format allows.
// Writers write the file at `path` (the caller passes a temporary path and renames it).

#include <cstdint>
#include <span>
#include <string>

#include "microbrdf/io.hpp"
#include "microbrdf/surface.hpp"

namespace microbrdf::detail {

using Bytes = std::span<const std::uint8_t>;

/// Asks the memory budget (microbrdf/memory_budget.hpp) before a reader allocates a height map
/// of `samples` points (8-byte height + 1-byte mask each) plus `extra` bytes of decoded payload,
/// for a file of `file_bytes` bytes. Throws FileError naming `name` and the bytes asked.
void check_surface_memory(const std::string& name, std::uint64_t file_bytes, std::uint64_t samples,
                          std::uint64_t extra = 0);

Surface read_x3p(Bytes data, const std::string& name);
void write_x3p(const Surface& s, const std::string& path);

Surface read_metropro_dat(Bytes data, const std::string& name);
Surface read_datx(Bytes data, const std::string& name);
Surface read_sur(Bytes data, const std::string& name);
Surface read_plu(Bytes data, const std::string& name);

Surface read_gwy(Bytes data, const std::string& name);
void write_gwy(const Surface& s, const std::string& path);

/// Text: "x y z" triples on a regular grid (any order, NaN/"nan"/"-" for invalid), or a plain
/// matrix of heights, one row per line (spacing from options). Lines starting with '#' or '%'
/// are comments; a "# dx_m = ..." style header written by write_ascii_grid is understood.
Surface read_ascii(Bytes data, const std::string& name, const ReadOptions& options);
void write_ascii_xyz(const Surface& s, const std::string& path);
void write_ascii_grid(const Surface& s, const std::string& path);

/// .npy float32/float64/int, C or Fortran order, 2-D. Spacing: options, else 1 m (the
/// dispatcher reads the JSON sidecar and passes it in options).
Surface read_npy(Bytes data, const std::string& name, const ReadOptions& options);
void write_npy(const Surface& s, const std::string& path);  // heights in metres, float64

/// Single-channel float image (first of Z/Y/R/... channels); spacing from options (required).
Surface read_exr(Bytes data, const std::string& name, const ReadOptions& options);
/// 32-bit float (or 16/32-bit integer) single-sample TIFF; spacing from options (required).
Surface read_tiff(Bytes data, const std::string& name, const ReadOptions& options);

}  // namespace microbrdf::detail
