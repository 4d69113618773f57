// Fresnel reflectance (include/microbrdf/fresnel.hpp; docs/theory.md §5.3-5.5).
#include "microbrdf/fresnel.hpp"

#include <algorithm>
#include <cmath>

#include "microbrdf/error.hpp"

namespace microbrdf {

double fresnel_conductor(double cos_i, std::complex<double> eta) {
  const double c = std::min(std::abs(cos_i), 1.0);
  const double sin2 = std::max(0.0, 1.0 - c * c);
  const std::complex<double> cos_t = std::sqrt(1.0 - sin2 / (eta * eta));
  const std::complex<double> rp = (eta * c - cos_t) / (eta * c + cos_t);
  const std::complex<double> rs = (c - eta * cos_t) / (c + eta * cos_t);
  return 0.5 * (std::norm(rp) + std::norm(rs));
}

double fresnel_conductor_siegel(double cos_i, double eta, double kappa) {
  const double c = std::min(std::abs(cos_i), 1.0);
  const double c2 = c * c, s2 = std::max(0.0, 1.0 - c2);
  const double t = eta * eta - kappa * kappa - s2;
  const double a2b2 = std::sqrt(t * t + 4 * eta * eta * kappa * kappa);
  const double a = std::sqrt(std::max(0.0, 0.5 * (a2b2 + t)));
  const double rs = (a2b2 - 2 * a * c + c2) / (a2b2 + 2 * a * c + c2);
  const double rp =
      rs * (a2b2 * c2 - 2 * a * c * s2 + s2 * s2) / (a2b2 * c2 + 2 * a * c * s2 + s2 * s2);
  return 0.5 * (rs + rp);
}

double fresnel_conductor_sun_as_printed(double cos_i, double eta, double kappa) {
  const double c = std::min(std::abs(cos_i), 1.0);
  const double s2 = std::max(0.0, 1.0 - c * c);
  const double t = eta * eta - kappa * kappa - s2;
  const double root = std::sqrt(t * t + 4 * eta * eta * kappa * kappa);
  const double a2 = 0.5 * (root + t * t);  // eq. 5.8 as printed (t squared)
  const double b2 = 0.5 * (root - t * t);
  const double a = std::sqrt(std::max(0.0, a2));
  const double e = eta * eta + kappa * kappa;
  const double rpar =
      (e * e * c * c - 2 * a * e * c + (a2 + b2)) / (e * e * c * c + 2 * a * e * c + (a2 + b2));
  const double rperp = (c * c - 2 * a * c + (a2 + b2)) / (c * c + 2 * a * c + (a2 + b2));
  return 0.5 * (rpar + rperp);
}

double fresnel_dielectric(double cos_i, double eta) {
  double c = std::clamp(cos_i, -1.0, 1.0);
  if (c < 0) {
    eta = 1.0 / eta;
    c = -c;
  }
  const double sin2_t = (1.0 - c * c) / (eta * eta);
  if (sin2_t >= 1.0) return 1.0;  // total internal reflection
  const double cos_t = std::sqrt(1.0 - sin2_t);
  const double rs = (c - eta * cos_t) / (c + eta * cos_t);
  const double rp = (eta * c - cos_t) / (eta * c + cos_t);
  return 0.5 * (rs * rs + rp * rp);
}

double fresnel_schlick(double cos_i, double r0) {
  const double m = 1.0 - std::min(std::abs(cos_i), 1.0);
  const double m2 = m * m;
  return r0 + (1.0 - r0) * m2 * m2 * m;
}

double normal_reflectance(double eta, double kappa) {
  return ((eta - 1) * (eta - 1) + kappa * kappa) / ((eta + 1) * (eta + 1) + kappa * kappa);
}

double kappa_from_normal_reflectance(double r0, double eta) {
  if (!(r0 >= 0 && r0 < 1))
    throw InputError("normal-incidence reflectance must lie in [0, 1), got " + std::to_string(r0));
  if (!(eta > 0)) throw InputError("refractive index eta must be positive");
  const double k2 = (r0 * (eta + 1) * (eta + 1) - (eta - 1) * (eta - 1)) / (1 - r0);
  if (k2 < 0)
    throw InputError("no absorbing index with eta = " + std::to_string(eta) +
                     " gives normal reflectance " + std::to_string(r0) +
                     " (it is below the dielectric value)");
  return std::sqrt(k2);
}

std::string ConductorFresnel::describe() const {
  return "conductor " + c_.name + (c_.source.empty() ? "" : " (" + c_.source + ")");
}

std::string DielectricFresnel::describe() const {
  return "dielectric, eta(550 nm) = " + std::to_string(eta_(550e-9));
}

}  // namespace microbrdf
