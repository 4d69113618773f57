// Tables for spectral rendering (see spectral.hpp).
#include "render/spectral.hpp"

#include <Eigen/Dense>

#include "microbrdf/spectrum.hpp"

namespace microbrdf::pt {

const SpectralTables& SpectralTables::get() {
  static const SpectralTables t;
  return t;
}

SpectralTables::SpectralTables() {
  const std::size_t n = std::size_t(kLambdaRangeNm * kStepsPerNm) + 1;
  const auto &x = cie1931_x(), &y = cie1931_y(), &z = cie1931_z(), &d65 = cie_d65();
  // Y_norm = integral D65 ybar over the range; the tables are piecewise linear in 5 nm steps, so
  // trapezoids on a 0.05 nm grid are exact to ~1e-7.
  double ynorm = 0;
  const int fine = 9400;
  for (int i = 0; i <= fine; ++i) {
    const double l = (kLambdaMinNm + kLambdaRangeNm * i / fine) * 1e-9;
    ynorm += (i == 0 || i == fine ? 0.5 : 1.0) * d65(l) * y(l) * (kLambdaRangeNm / fine);
  }
  // Three in-gamut colours c_i (columns of M, rows summing to 1) and smooth spectra T_i with
  // those colours; T_3 = 1 - T_1 - T_2 has colour 1 - c_1 - c_2 = c_3 by linearity. The basis
  // S = T M^-1 then has colours e_r, e_g, e_b and S_r + S_g + S_b = T M^-1 1 = T 1 = 1.
  const double a = 0.8, b = 0.1;
  Eigen::Matrix3d m;
  m << a, b, b, b, a, b, b, b, a;
  const Spectrum t1 = smooth_reflectance_from_linear_srgb(Eigen::Vector3d(a, b, b));
  const Spectrum t2 = smooth_reflectance_from_linear_srgb(Eigen::Vector3d(b, a, b));
  const Eigen::Matrix3d minv = m.inverse();
  xyz_.resize(n);
  basis_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double l = (kLambdaMinNm + double(i) / kStepsPerNm) * 1e-9;
    xyz_[i] = Eigen::Vector3d(x(l), y(l), z(l)) * d65(l) * kLambdaRangeNm / ynorm;
    const Eigen::Vector3d t(t1(l), t2(l), 1 - t1(l) - t2(l));
    basis_[i] = minv.transpose() * t;  // S_c = sum_i T_i (M^-1)_{i c}
  }
}

}  // namespace microbrdf::pt
