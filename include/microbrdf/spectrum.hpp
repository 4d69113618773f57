#pragma once
// Sampled spectra and colour: CIE 1931 2-degree observer, D65, XYZ and sRGB.
//
// Units: wavelengths are metres everywhere in the API unless a name says "nm". A Spectrum is
// piecewise linear between its samples and constant beyond its first and last sample.
//
// Colour of a reflectance spectrum R(lambda) (see docs/models.md):
//   X = sum_l R(l) S(l) xbar(l) / sum_l S(l) ybar(l)   (same for Y, Z),
// with S = CIE D65 and xbar, ybar, zbar the CIE 1931 2-degree colour matching functions, summed
// on their 5 nm grid 360..830 nm (CIE 15 practice; tables from Debian's colord-data package,
// generated into the build at build time). A perfect white reflector (R = 1) has Y = 1 and
// linear sRGB (1, 1, 1) up to the rounding of the 5 nm tables (< 3e-4).
// Linear sRGB uses the IEC 61966-2-1 primaries and D65 white; the matrix is computed from the
// chromaticities (x, y) = (0.64, 0.33), (0.30, 0.60), (0.15, 0.06), white (0.3127, 0.3290).

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace microbrdf {

class Spectrum {
 public:
  Spectrum() = default;
  /// Samples at strictly increasing wavelengths (metres). Throws InputError otherwise.
  Spectrum(std::vector<double> wavelengths_m, std::vector<double> values);
  /// Same with wavelengths in nanometres.
  static Spectrum from_nm(const std::vector<double>& wavelengths_nm, std::vector<double> values);
  /// A wavelength-independent value.
  static Spectrum constant(double value);

  /// Linear interpolation; constant extrapolation beyond the ends. 0 for an empty spectrum.
  double operator()(double wavelength_m) const;
  double at_nm(double wavelength_nm) const { return (*this)(wavelength_nm * 1e-9); }

  bool empty() const { return values_.empty(); }
  std::size_t size() const { return values_.size(); }
  const std::vector<double>& wavelengths() const { return lambda_; }  ///< metres
  const std::vector<double>& values() const { return values_; }
  double min_wavelength() const { return lambda_.empty() ? 0 : lambda_.front(); }
  double max_wavelength() const { return lambda_.empty() ? 0 : lambda_.back(); }

 private:
  std::vector<double> lambda_;
  std::vector<double> values_;
};

/// The CIE 1931 2-degree colour matching functions (xbar, ybar, zbar), 360..830 nm every 5 nm.
const Spectrum& cie1931_x();
const Spectrum& cie1931_y();
const Spectrum& cie1931_z();
/// CIE standard illuminant D65, relative SPD, 300..830 nm every 5 nm, 1 at 560 nm.
const Spectrum& cie_d65();
/// The wavelengths (metres) of the colour-matching grid, 360..830 nm every 5 nm.
const std::vector<double>& colour_wavelengths();

/// XYZ of a reflectance under D65, normalised so that R = 1 gives Y = 1.
Eigen::Vector3d reflectance_to_xyz(const std::function<double(double wavelength_m)>& reflectance);
Eigen::Vector3d reflectance_to_xyz(const Spectrum& reflectance);

/// XYZ -> linear sRGB (D65 white, no chromatic adaptation needed) and back.
Eigen::Matrix3d xyz_to_linear_srgb_matrix();
Eigen::Vector3d xyz_to_linear_srgb(const Eigen::Vector3d& xyz);
Eigen::Vector3d linear_srgb_to_xyz(const Eigen::Vector3d& rgb);

/// sRGB transfer function (IEC 61966-2-1) on [0, 1] (values are clamped to [0, 1] first).
double srgb_encode(double linear);
double srgb_decode(double encoded);
/// Linear sRGB -> 8-bit sRGB (clamped, rounded).
std::array<std::uint8_t, 3> linear_srgb_to_srgb8(const Eigen::Vector3d& rgb);
/// "#rrggbb".
std::string srgb8_hex(const std::array<std::uint8_t, 3>& c);

/// A smooth reflectance spectrum with a given colour (Jakob & Hanika 2019 style):
///   R(lambda) = 1/2 + x / (2 sqrt(1 + x^2)),  x = c0 t^2 + c1 t + c2,  t = (lambda - 595 nm)/235
///   nm,
/// bounded in (0, 1) and smooth, with (c0, c1, c2) found by damped Gauss-Newton so that the
/// linear sRGB of R under D65 equals `linear_rgb`. Throws InputError if the colour is outside
/// what a reflectance can give (a component outside (0, 1) after the fit's tolerance 1e-6).
Spectrum smooth_reflectance_from_linear_srgb(const Eigen::Vector3d& linear_rgb);

}  // namespace microbrdf
