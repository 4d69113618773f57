#pragma once
// Levelling: least-squares removal of a plane or a low-order 2-D polynomial, fitted to the
// valid samples only. Measured data are levelled with a plane by default (the CLI reports it).

#include <string>
#include <vector>

#include "microbrdf/surface.hpp"

namespace microbrdf {

enum class Leveling { None, Plane, Polynomial };

struct LevelingSpec {
  Leveling mode = Leveling::Plane;
  int degree = 2;  ///< total degree for Polynomial (1 = plane), 1..6
  /// "none", "plane", "poly2", "poly3", ...
  std::string name() const;
  /// Parses "none", "plane", "poly", "polyN" (poly = poly2). Throws InputError.
  static LevelingSpec parse(const std::string& text);
};

struct LevelingResult {
  std::string description;           ///< e.g. "plane (tilt 0.012 deg, rms removed 2.83 um)"
  std::vector<double> coefficients;  ///< of u^i v^j (graded order 1, u, v, u^2, uv, v^2, ...), m;
                                     ///< u, v = coordinates scaled to [-1, 1] over the grid
  double rms_before = 0;             ///< rms about the mean before levelling, m
  double rms_after = 0;              ///< rms about the mean after levelling, m
};

/// Fits and subtracts the polynomial (in place). The fitted value at the grid centre goes into
/// surface.z0 (so z + z0 stays the absolute height there), and surface.meta.leveling is set.
/// Leveling::None only records "none". Throws InputError if too few valid samples.
LevelingResult level_surface(Surface& surface, const LevelingSpec& spec);

}  // namespace microbrdf
