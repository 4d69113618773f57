#pragma once
// The angle <-> unit-square coordinates of the RGL `.bsdf` format (docs/measured.md): the
// renderers' u_theta = sqrt(2 theta / pi) (fine near the pole) and u_phi = (phi + pi) / (2 pi).
#include <algorithm>
#include <cmath>

namespace microbrdf::detail::rgl {

constexpr double kPi = 3.14159265358979323846;
inline double u2theta(double u) { return u * u * (kPi / 2); }
inline double u2phi(double u) { return (2 * u - 1) * kPi; }
inline double theta2u(double t) { return std::sqrt(std::max(0.0, t) * (2 / kPi)); }
inline double phi2u(double p) { return (p + kPi) / (2 * kPi); }
/// Jacobian of (u_theta, u_phi) -> solid angle: dw = 2 pi^2 u_theta sin(theta) du_theta du_phi
/// (floored as the renderers do).
inline double solid_angle_jacobian(double u_theta, double theta) {
  return std::max(2 * kPi * kPi * u_theta * std::sin(theta), 1e-6);
}

}  // namespace microbrdf::detail::rgl
