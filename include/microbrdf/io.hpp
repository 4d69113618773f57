#pragma once
// Reading and writing height maps in instrument and exchange formats.
//
// Readers bound every allocation by what the file can justify (a header claiming a grid larger
// than the bytes that follow is an error, not an allocation), and report problems as
// FileError("<path>: <problem>"). Writers are atomic: they write a temporary file next to the
// target and rename it, so a failed write leaves no partial file.

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "microbrdf/file_read.hpp"
#include "microbrdf/surface.hpp"

namespace microbrdf {

enum class SurfaceFormat {
  Auto,         ///< from the extension, then the magic bytes
  X3p,          ///< OpenGPS / ISO 25178-72 (.x3p), read + write
  MetroProDat,  ///< Zygo MetroPro binary (.dat), read
  Datx,         ///< Zygo HDF5 (.datx), read
  Sur,          ///< Digital Surf (.sur), read
  Plu,          ///< Sensofar (.plu), read
  Gwy,          ///< Gwyddion native (.gwy), read + write
  AsciiXyz,     ///< text "x y z" per line (.xyz), read + write
  AsciiGrid,    ///< text matrix, one row per line (.txt, .asc, .csv), read + write
  Npy,          ///< NumPy array (.npy) + JSON sidecar for spacing, read + write
  Exr,          ///< float OpenEXR height image (.exr), read (spacing required)
  Tiff,         ///< 32-bit float TIFF height image (.tif, .tiff), read (spacing required)
};

struct ReadOptions {
  /// Spacing for formats that do not store it (npy without sidecar, exr, tiff, ascii grid),
  /// metres. Also overrides a stored spacing when set (e.g. uncalibrated Zygo files).
  std::optional<double> dx, dy;
  /// The height of one stored unit, metres, for formats that store no height unit (TIFF, EXR,
  /// .npy, text grids): heights are the file's numbers times this. Integer TIFF images without
  /// a `z_unit` in their ImageDescription need it (counts have no unit); formats that store a
  /// unit (x3p, dat, datx, sur, plu, gwy) refuse it.
  std::optional<double> z_scale;
  /// Refuse files larger than this (bytes); guards against absurd inputs.
  std::uint64_t max_file_bytes = std::uint64_t{8} << 30;
};

/// Reads a height map. Format from `format`, else from the extension, else from magic bytes.
/// Throws FileError.
Surface read_surface(const std::string& path, const ReadOptions& options = {},
                     SurfaceFormat format = SurfaceFormat::Auto);

/// Parses a height map held in memory; `name` is used in error messages. This is what the
/// fuzz targets call. The npy sidecar is not consulted here (spacing from options or 1 m).
Surface read_surface_bytes(std::span<const std::uint8_t> data, SurfaceFormat format,
                           const std::string& name, const ReadOptions& options = {});

/// Writes a height map atomically. Format from `format`, else from the extension.
/// Throws FileError (unwritable path, format that cannot be written).
void write_surface(const Surface& surface, const std::string& path,
                   SurfaceFormat format = SurfaceFormat::Auto);

/// The format an extension names (Auto when unknown).
SurfaceFormat format_from_extension(const std::string& path);
/// The format magic bytes identify (Auto when none matches).
SurfaceFormat format_from_magic(std::span<const std::uint8_t> head);
/// Short name: "x3p", "dat", "datx", ...
std::string format_name(SurfaceFormat format);
bool format_can_write(SurfaceFormat format);
/// Whether the format needs ReadOptions::dx/dy (no spacing stored).
bool format_needs_spacing(SurfaceFormat format);

}  // namespace microbrdf
