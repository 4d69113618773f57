#pragma once
// Spectral rendering helpers: hero wavelengths, RGB -> spectrum upsampling of light sources and
// the spectrum -> XYZ estimator.
//
// Radiance is carried as a spectrum relative to D65: a spectral value L(lambda) stands for the
// physical radiance L(lambda) D65(lambda) / k, so L = 1 at every wavelength is the D65 white of
// luminance Y = 1 and linear sRGB (1, 1, 1). XYZ = integral L D65 cmf dlambda / integral D65 ybar
// over 360..830 nm, estimated per path with `n` hero wavelengths l_k = 360 nm + (l_0 - 360 nm +
// k 470 nm / n) mod 470 nm, l_0 uniform: each l_k is uniform on [360, 830) nm, so
// XYZ ~= sum_k L(l_k) D65(l_k) cmf(l_k) 470 nm / (n Y_norm).
// Upsampling: rgb -> r S_r + g S_g + b S_b with three fixed spectra whose linear sRGB colours
// are exactly (1,0,0), (0,1,0), (0,0,1) and whose sum is exactly 1 (flat white), built from
// smooth reflectance spectra (spectrum.hpp) of three in-gamut colours and a linear change of basis.

#include <Eigen/Core>
#include <array>
#include <vector>

namespace microbrdf::pt {

constexpr double kLambdaMinNm = 360, kLambdaMaxNm = 830, kLambdaRangeNm = 470;
constexpr int kMaxWavelengths = 16;

class SpectralTables {
 public:
  /// The tables (built once, thread-safe).
  static const SpectralTables& get();

  /// D65(l) (xbar, ybar, zbar)(l) 470 nm / Y_norm: one hero sample's XYZ weight for L = 1.
  Eigen::Vector3d xyz_weight(double lambda_nm) const { return lerp(xyz_, lambda_nm); }
  /// The three upsampling basis spectra at l.
  Eigen::Vector3d basis(double lambda_nm) const { return lerp(basis_, lambda_nm); }
  /// Spectral value of an RGB light at l.
  double upsample(const Eigen::Vector3d& rgb, double lambda_nm) const {
    return rgb.dot(basis(lambda_nm));
  }

 private:
  SpectralTables();
  static Eigen::Vector3d lerp(const std::vector<Eigen::Vector3d>& t, double nm) {
    const double x = std::clamp((nm - kLambdaMinNm) * kStepsPerNm, 0.0, double(t.size() - 1));
    const std::size_t i = std::min(std::size_t(x), t.size() - 2);
    const double f = x - double(i);
    return (1 - f) * t[i] + f * t[i + 1];
  }
  static constexpr double kStepsPerNm = 2;  // tables every 0.5 nm
  std::vector<Eigen::Vector3d> xyz_, basis_;
};

/// The hero wavelengths (nm) of one path.
inline void hero_wavelengths(double u, int n, double* out) {
  const double l0 = kLambdaRangeNm * u;
  for (int k = 0; k < n; ++k) {
    double l = l0 + k * kLambdaRangeNm / n;
    if (l >= kLambdaRangeNm) l -= kLambdaRangeNm;
    out[k] = kLambdaMinNm + l;
  }
}

}  // namespace microbrdf::pt
