#pragma once
// D of the Beckmann, GGX and ellipsoid NDFs, written once as templates (T = double or a
// ceres::Jet): the distributions of microfacet.hpp evaluate these, and the fits differentiate
// them (ndf_model_template.hpp). Values in the order of the models' params(); m = (x, y, z) a
// unit vector with z > 0.
#include <cmath>

namespace microbrdf::lobes {

inline constexpr double kPi = 3.14159265358979323846;

/// (alpha_x, alpha_y, phi): the in-plane frame turned by phi, 1 / alpha^2 and 1 / (pi ax ay).
template <typename T>
struct Anisotropic {
  T c, s, iax2, iay2, norm;
  explicit Anisotropic(const T* v) {
    using std::cos;
    using std::sin;
    c = cos(v[2]);
    s = sin(v[2]);
    iax2 = T(1) / (v[0] * v[0]);
    iay2 = T(1) / (v[1] * v[1]);
    norm = T(1) / (T(kPi) * v[0] * v[1]);
  }
  /// x^2 / alpha_x^2 + y^2 / alpha_y^2 in the rotated frame.
  T stretched(double x, double y) const {
    const T u = c * x + s * y, w = -s * x + c * y;
    return u * u * iax2 + w * w * iay2;
  }
};

/// GGX: 1 / (pi ax ay (x^2/ax^2 + y^2/ay^2 + z^2)^2).
template <typename T>
struct Ggx : Anisotropic<T> {
  explicit Ggx(const T* v) : Anisotropic<T>(v) {}
  T D(double x, double y, double z) const {
    const T q = this->stretched(x, y) + T(z * z);
    return this->norm / (q * q);
  }
};

/// Beckmann: exp(-(x^2/ax^2 + y^2/ay^2) / z^2) / (pi ax ay z^4).
template <typename T>
struct Beckmann : Anisotropic<T> {
  explicit Beckmann(const T* v) : Anisotropic<T>(v) {}
  T D(double x, double y, double z) const {
    using std::exp;
    const double iz2 = 1 / (z * z);
    return exp(-this->stretched(x, y) * iz2) * this->norm * (iz2 * iz2);
  }
};

/// Ellipsoid (Dong 2015 eq. 10), values (alpha_x, alpha_y, theta_x, theta_y, theta_z):
/// 1 / (pi ax ay ||A n|| ||S^-1 R m||^4), R = Rx Ry Rz.
template <typename T>
struct Ellipsoid {
  T m[3][3];  // S^-1 R
  T norm;
  explicit Ellipsoid(const T* v) {
    using std::cos;
    using std::sin;
    using std::sqrt;
    const T ax = v[0], ay = v[1];
    const T cx = cos(v[2]), sx = sin(v[2]), cy = cos(v[3]), sy = sin(v[3]), cz = cos(v[4]),
            sz = sin(v[4]);
    const T r[3][3] = {{cy * cz, -cy * sz, sy},
                       {sx * sy * cz + cx * sz, -sx * sy * sz + cx * cz, -sx * cy},
                       {-cx * sy * cz + sx * sz, cx * sy * sz + sx * cz, cx * cy}};
    for (int j = 0; j < 3; ++j) {
      m[0][j] = r[0][j] / ax;
      m[1][j] = r[1][j] / ay;
      m[2][j] = r[2][j];
    }
    const T an =
        sqrt(ax * ax * r[0][2] * r[0][2] + ay * ay * r[1][2] * r[1][2] + r[2][2] * r[2][2]);
    norm = T(1) / (T(kPi) * ax * ay * an);
  }
  T D(double x, double y, double z) const {
    const T a = m[0][0] * x + m[0][1] * y + m[0][2] * z;
    const T b = m[1][0] * x + m[1][1] * y + m[1][2] * z;
    const T c = m[2][0] * x + m[2][1] * y + m[2][2] * z;
    const T q = a * a + b * b + c * c;
    return norm / (q * q);
  }
};

}  // namespace microbrdf::lobes
