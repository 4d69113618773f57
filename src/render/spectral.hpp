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
#include <algorithm>
#include <array>
#include <cmath>
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

/// The hero wavelengths (nm) of one path, uniform on [360, 830) nm (each l_k uniform).
inline void hero_wavelengths(double u, int n, double* out) {
  const double l0 = kLambdaRangeNm * u;
  for (int k = 0; k < n; ++k) {
    double l = l0 + k * kLambdaRangeNm / n;
    if (l >= kLambdaRangeNm) l -= kLambdaRangeNm;
    out[k] = kLambdaMinNm + l;
  }
}

/// Importance sampling of visible wavelengths (the density of the pbrt-v4 book, section 4.6.5,
/// roughly the shape of the colour matching functions times D65): l(u) = 538 - A atanh(B - C u)
/// with density p(l) = sech^2((l - 538) / A) / (A C) per nm, which is exactly that of the map
/// (dl/du = A C / (1 - (B - C u)^2)). l(0) = 360 nm, l(1) = 830.04 nm.
struct VisibleWavelengths {
  static constexpr double kA = 138.888889, kB = 0.85691062, kC = 1.82750197;
  static double sample(double u) {
    const double x = kB - kC * u;
    return 538 - kA * 0.5 * std::log((1 + x) / (1 - x));  // atanh(x)
  }
  static double pdf(double l_nm) {
    const double c = std::cosh((l_nm - 538) / kA);
    return 1 / (kA * kC * c * c);
  }
};

/// l(i / 1024), i = 0..1024: the map tabulated; the renderer draws from the piecewise-linear map
/// through these nodes, whose density is exactly 1 / (1024 (l_{i+1} - l_i)) on segment i (within
/// 3% of p(l); no log per wavelength).
inline const std::array<double, 1025>& visible_wavelength_nodes() {
  static const std::array<double, 1025> t = [] {
    std::array<double, 1025> a{};
    for (std::size_t i = 0; i < a.size(); ++i) a[i] = VisibleWavelengths::sample(double(i) / 1024);
    return a;
  }();
  return t;
}

/// The hero wavelengths (nm) of one path: l_k = m((u + k / n) mod 1) with m the piecewise-linear
/// map through visible_wavelength_nodes(), each with density q(l_k) (that of the map);
/// `weight[k]` = 1 / (470 nm q(l_k)) inside [360, 830] nm, else 0 (the factor that turns the
/// uniform estimator's XYZ weight into this one's).
inline void visible_hero_wavelengths(double u, int n, double* out, double* weight) {
  const auto& t = visible_wavelength_nodes();
  for (int k = 0; k < n; ++k) {
    double uk = u + double(k) / n;
    if (uk >= 1) uk -= 1;
    const double x = uk * 1024;
    const std::size_t i = std::min(std::size_t(x), std::size_t(1023));
    const double width = t[i + 1] - t[i], l = t[i] + (x - double(i)) * width;
    out[k] = std::clamp(l, kLambdaMinNm, kLambdaMaxNm);
    weight[k] = l >= kLambdaMinNm && l <= kLambdaMaxNm ? 1024 * width / kLambdaRangeNm : 0.0;
  }
}

}  // namespace microbrdf::pt
