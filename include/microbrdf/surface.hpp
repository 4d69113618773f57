#pragma once
// The Surface model: a measured or generated height map.
//
// Conventions (docs/architecture.md):
//  - Row-major storage z[iy*nx + ix]; x = x0 + ix*dx (columns), y = y0 + iy*dy (rows).
//  - Readers keep the file's storage order: iy = 0 is the first row stored in the file, and
//    y grows with the storage row. Nothing is flipped. (Formats disagree on whether the first
//    row is the top or bottom of the sample; see docs/formats.md.)
//  - Heights in metres. Invalid samples are NaN in z and 0 in `valid`; the two always agree
//    (see Surface::check()). Nothing is silently interpolated.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace microbrdf {

/// What the source file said about where the data came from. Empty strings mean "not stated".
struct SurfaceMetadata {
  std::string source_path;        ///< file the surface was read from ("" when generated)
  std::string format;             ///< "x3p", "metropro-dat", "datx", "sur", "plu", "gwy", ...
  std::string instrument;         ///< manufacturer / model / serial as the file states them
  std::string date;               ///< measurement date as the file states it
  std::string comment;            ///< free text from the file
  std::string z_unit_in_file;     ///< the unit heights were stored in ("m", "um", "fringes", ...)
  std::string leveling = "none";  ///< what levelling was applied: none|plane|poly<N>
  /// Anything else worth keeping (objective, wavelength, generator parameters...).
  std::vector<std::pair<std::string, std::string>> extra;

  void set(const std::string& key, const std::string& value);
  std::string get(const std::string& key) const;  ///< "" when absent
};

struct Surface {
  std::size_t nx = 0;  ///< samples per row (x, fast index)
  std::size_t ny = 0;  ///< rows (y)
  double dx = 0;       ///< spacing along x, metres (> 0)
  double dy = 0;       ///< spacing along y, metres (> 0)
  double x0 = 0;       ///< x of column 0, metres
  double y0 = 0;       ///< y of row 0, metres
  double z0 = 0;       ///< offset removed from the heights by levelling, metres (absolute = z+z0)
  std::vector<double> z;            ///< heights, metres; NaN where invalid
  std::vector<std::uint8_t> valid;  ///< 1 = measured, 0 = invalid
  SurfaceMetadata meta;

  Surface() = default;
  /// A flat, fully valid surface of nx x ny samples, spacing dx, dy (metres).
  Surface(std::size_t nx, std::size_t ny, double dx, double dy);

  std::size_t size() const { return nx * ny; }
  std::size_t index(std::size_t ix, std::size_t iy) const { return iy * nx + ix; }
  double& at(std::size_t ix, std::size_t iy) { return z[iy * nx + ix]; }
  double at(std::size_t ix, std::size_t iy) const { return z[iy * nx + ix]; }
  bool is_valid(std::size_t i) const { return valid[i] != 0; }

  /// Marks sample i invalid (z = NaN, valid = 0).
  void invalidate(std::size_t i) {
    z[i] = std::numeric_limits<double>::quiet_NaN();
    valid[i] = 0;
  }
  /// Makes the mask agree with z: every non-finite height (NaN, +-Inf) becomes NaN + invalid,
  /// and every sample already marked invalid gets NaN. Call after filling z.
  void sync_mask();
  std::size_t valid_count() const;
  /// Mean height of the valid samples, metres (NaN if there are none).
  double valid_mean() const;
  double valid_fraction() const;
  double width() const { return static_cast<double>(nx) * dx; }   ///< metres
  double height() const { return static_cast<double>(ny) * dy; }  ///< metres

  /// Throws std::logic_error if sizes, spacing or mask/NaN agreement are broken.
  void check() const;
};

}  // namespace microbrdf
