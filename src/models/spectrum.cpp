// Sampled spectra, CIE colorimetry and sRGB (include/microbrdf/spectrum.hpp).
#include "microbrdf/spectrum.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "microbrdf/error.hpp"
#include "models/tables.hpp"

namespace microbrdf {

Spectrum::Spectrum(std::vector<double> wavelengths_m, std::vector<double> values)
    : lambda_(std::move(wavelengths_m)), values_(std::move(values)) {
  if (lambda_.size() != values_.size())
    throw InputError("spectrum: " + std::to_string(lambda_.size()) + " wavelengths but " +
                     std::to_string(values_.size()) + " values");
  for (std::size_t i = 0; i < lambda_.size(); ++i) {
    if (!std::isfinite(lambda_[i]) || !std::isfinite(values_[i]))
      throw InputError("spectrum: non-finite wavelength or value at sample " + std::to_string(i));
    if (i > 0 && !(lambda_[i] > lambda_[i - 1]))
      throw InputError("spectrum: wavelengths must increase strictly (sample " + std::to_string(i) +
                       ")");
  }
}

Spectrum Spectrum::from_nm(const std::vector<double>& wavelengths_nm, std::vector<double> values) {
  std::vector<double> m(wavelengths_nm.size());
  for (std::size_t i = 0; i < m.size(); ++i) m[i] = wavelengths_nm[i] * 1e-9;
  return Spectrum(std::move(m), std::move(values));
}

Spectrum Spectrum::constant(double value) { return Spectrum({550e-9}, {value}); }

double Spectrum::operator()(double wavelength_m) const {
  const std::size_t n = values_.size();
  if (n == 0) return 0;
  if (n == 1 || wavelength_m <= lambda_.front()) return values_.front();
  if (wavelength_m >= lambda_.back()) return values_.back();
  auto it = std::upper_bound(lambda_.begin(), lambda_.end(), wavelength_m);
  std::size_t i = static_cast<std::size_t>(it - lambda_.begin());  // lambda_[i-1] <= w < lambda_[i]
  double t = (wavelength_m - lambda_[i - 1]) / (lambda_[i] - lambda_[i - 1]);
  return values_[i - 1] + t * (values_[i] - values_[i - 1]);
}

namespace {

Spectrum uniform_table(double start_nm, double end_nm, std::size_t bands, const double* v) {
  std::vector<double> nm(bands), val(v, v + bands);
  double step = (end_nm - start_nm) / static_cast<double>(bands - 1);
  for (std::size_t i = 0; i < bands; ++i) nm[i] = start_nm + step * static_cast<double>(i);
  return Spectrum::from_nm(nm, std::move(val));
}

// Weights of the colour sums on the CMF grid: w_c(l) = S(l) cbar(l) / sum S ybar.
struct ColourWeights {
  std::vector<double> lambda;
  std::vector<Eigen::Vector3d> w;
};

const ColourWeights& colour_weights() {
  static const ColourWeights cw = [] {
    ColourWeights c;
    const auto& x = cie1931_x();
    c.lambda = x.wavelengths();
    double norm = 0;
    for (std::size_t i = 0; i < c.lambda.size(); ++i) {
      double s = cie_d65()(c.lambda[i]);
      c.w.emplace_back(s * detail::kCmfX[i], s * detail::kCmfY[i], s * detail::kCmfZ[i]);
      norm += s * detail::kCmfY[i];
    }
    for (auto& v : c.w) v /= norm;
    return c;
  }();
  return cw;
}

}  // namespace

const Spectrum& cie1931_x() {
  static const Spectrum s =
      uniform_table(detail::kCmfStartNm, detail::kCmfEndNm, detail::kCmfBands, detail::kCmfX);
  return s;
}
const Spectrum& cie1931_y() {
  static const Spectrum s =
      uniform_table(detail::kCmfStartNm, detail::kCmfEndNm, detail::kCmfBands, detail::kCmfY);
  return s;
}
const Spectrum& cie1931_z() {
  static const Spectrum s =
      uniform_table(detail::kCmfStartNm, detail::kCmfEndNm, detail::kCmfBands, detail::kCmfZ);
  return s;
}
const Spectrum& cie_d65() {
  static const Spectrum s =
      uniform_table(detail::kD65StartNm, detail::kD65EndNm, detail::kD65Bands, detail::kD65);
  return s;
}
const std::vector<double>& colour_wavelengths() { return cie1931_x().wavelengths(); }

Eigen::Vector3d reflectance_to_xyz(const std::function<double(double)>& reflectance) {
  const auto& cw = colour_weights();
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < cw.lambda.size(); ++i) xyz += reflectance(cw.lambda[i]) * cw.w[i];
  return xyz;
}

Eigen::Vector3d reflectance_to_xyz(const Spectrum& reflectance) {
  return reflectance_to_xyz([&](double l) { return reflectance(l); });
}

Eigen::Matrix3d xyz_to_linear_srgb_matrix() {
  static const Eigen::Matrix3d m = [] {
    auto col = [](double x, double y) { return Eigen::Vector3d(x / y, 1.0, (1 - x - y) / y); };
    Eigen::Matrix3d p;
    p.col(0) = col(0.64, 0.33);
    p.col(1) = col(0.30, 0.60);
    p.col(2) = col(0.15, 0.06);
    Eigen::Vector3d s = p.lu().solve(col(0.3127, 0.3290));
    Eigen::Matrix3d rgb_to_xyz = p * s.asDiagonal();
    return Eigen::Matrix3d(rgb_to_xyz.inverse());
  }();
  return m;
}

Eigen::Vector3d xyz_to_linear_srgb(const Eigen::Vector3d& xyz) {
  return xyz_to_linear_srgb_matrix() * xyz;
}
Eigen::Vector3d linear_srgb_to_xyz(const Eigen::Vector3d& rgb) {
  return xyz_to_linear_srgb_matrix().inverse() * rgb;
}

double srgb_encode(double linear) {
  if (!(linear < 1)) return linear >= 1 ? 1.0 : 0.0;  // clipped exactly (NaN shows as black)
  double c = std::max(linear, 0.0);
  return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
}

double srgb_decode(double encoded) {
  double c = std::clamp(encoded, 0.0, 1.0);
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

std::array<std::uint8_t, 3> linear_srgb_to_srgb8(const Eigen::Vector3d& rgb) {
  std::array<std::uint8_t, 3> out{};
  for (int i = 0; i < 3; ++i)
    out[i] = static_cast<std::uint8_t>(std::lround(255.0 * srgb_encode(rgb[i])));
  return out;
}

std::string srgb8_hex(const std::array<std::uint8_t, 3>& c) {
  char b[8];
  std::snprintf(b, sizeof b, "#%02x%02x%02x", c[0], c[1], c[2]);
  return b;
}

namespace {
double sigmoid(double x) { return 0.5 + x / (2 * std::sqrt(1 + x * x)); }
double poly_t(double lambda_m) { return (lambda_m - 595e-9) / 235e-9; }
Eigen::Vector3d smooth_rgb(const Eigen::Vector3d& c) {
  return xyz_to_linear_srgb(reflectance_to_xyz([&](double l) {
    double t = poly_t(l);
    return sigmoid((c[0] * t + c[1]) * t + c[2]);
  }));
}
}  // namespace

Spectrum smooth_reflectance_from_linear_srgb(const Eigen::Vector3d& linear_rgb) {
  for (int i = 0; i < 3; ++i)
    if (!(linear_rgb[i] > 0 && linear_rgb[i] < 1))
      throw InputError(
          "colour: linear sRGB components must lie strictly between 0 and 1 for a reflectance");
  // Start from a flat spectrum with the colour's luminance.
  double y = std::clamp(2 * linear_srgb_to_xyz(linear_rgb)[1] - 1, -0.999, 0.999);
  Eigen::Vector3d c(0, 0, y / std::sqrt(1 - y * y));
  Eigen::Vector3d r = smooth_rgb(c) - linear_rgb;
  double mu = 1e-3;
  for (int it = 0; it < 200 && r.norm() > 1e-12; ++it) {
    Eigen::Matrix3d j;
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d d = Eigen::Vector3d::Zero();
      d[k] = 1e-6 * std::max(1.0, std::abs(c[k]));
      j.col(k) = (smooth_rgb(c + d) - smooth_rgb(c - d)) / (2 * d[k]);
    }
    Eigen::Matrix3d a = j.transpose() * j;
    Eigen::Vector3d g = j.transpose() * r;
    for (;;) {
      Eigen::Matrix3d damped = a;
      damped.diagonal() *= 1 + mu;
      Eigen::Vector3d step = damped.ldlt().solve(-g);
      Eigen::Vector3d r2 = smooth_rgb(c + step) - linear_rgb;
      if (r2.norm() < r.norm()) {
        c += step;
        r = r2;
        mu = std::max(mu * 0.3, 1e-9);
        break;
      }
      mu *= 10;
      if (mu > 1e12) break;
    }
    if (mu > 1e12) break;
  }
  if (r.norm() > 1e-6)
    throw InputError(
        "colour: no smooth reflectance spectrum reproduces this sRGB colour (residual " +
        std::to_string(r.norm()) + "); it is too saturated for a reflectance");
  std::vector<double> lambda = colour_wavelengths(), v(lambda.size());
  for (std::size_t i = 0; i < lambda.size(); ++i) {
    double t = poly_t(lambda[i]);
    v[i] = sigmoid((c[0] * t + c[1]) * t + c[2]);
  }
  return Spectrum(std::move(lambda), std::move(v));
}

}  // namespace microbrdf
