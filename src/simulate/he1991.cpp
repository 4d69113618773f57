// He et al. 1991 in the geometric-optics limit (docs/theory.md §6.7): the reference for W92 Fig. 6.
#include <algorithm>
#include <cmath>

#include "microbrdf/simulate.hpp"

namespace microbrdf {
namespace {

// He eqs. 24-25: S = (1 - erfc(a)/2) / (1 + Lambda(a)), a = tau cot(theta) / (2 sigma).
double he_shadowing(double cos_t, double sigma, double tau, bool errata) {
  if (cos_t >= 1) return 1;
  const double sin_t = std::sqrt(std::max(0.0, 1 - cos_t * cos_t));
  const double a = tau * cos_t / (2 * sigma * sin_t);
  if (!(a > 0)) return 0;
  const double e = errata ? std::exp(-a * a) : 1.0;
  const double lambda = 0.5 * (e / (std::sqrt(M_PI) * a) - std::erfc(a));
  return (1 - 0.5 * std::erfc(a)) / (1 + lambda);
}

// K = tan(theta) erfc(tau / (2 sigma tan(theta))).
double he_k(double cos_t, double sigma, double tau) {
  const double sin_t = std::sqrt(std::max(0.0, 1 - cos_t * cos_t));
  if (sin_t == 0) return 0;
  const double tan_t = sin_t / cos_t;
  return tan_t * std::erfc(tau / (2 * sigma * tan_t));
}

}  // namespace

double he1991_geometric_brdf(const Eigen::Vector3d& wi, const Eigen::Vector3d& wo, double sigma,
                             double tau, bool errata, const Fresnel* fresnel, double wavelength_m) {
  const double ci = wi.z(), co = wo.z();
  if (!(ci > 0) || !(co > 0)) return 0;
  // Effective roughness: x e^{x^2/2} = (K_i + K_r) / sqrt(8 pi), x = z0 / sigma (Newton; the
  // function is convex and increasing, so the iteration converges from the right).
  const double c = (he_k(ci, sigma, tau) + he_k(co, sigma, tau)) / std::sqrt(8 * M_PI);
  double x = c;
  for (int it = 0; it < 60; ++it) {
    const double ex = std::exp(0.5 * x * x);
    const double dx = (x * ex - c) / (ex * (1 + x * x));
    x -= dx;
    if (std::abs(dx) < 1e-15) break;
  }
  const double sigma0 = sigma / std::sqrt(1 + x * x);
  const double alpha = 2 * sigma0 / tau;
  const Eigen::Vector3d h = (wi + wo).normalized();
  const double ch = h.z();
  if (!(ch > 0)) return 0;
  const double tan2 = (1 - ch * ch) / (ch * ch);
  const double d = std::exp(-tan2 / (alpha * alpha)) / (M_PI * alpha * alpha * ch * ch * ch * ch);
  const double f = fresnel ? fresnel->eval(wi.dot(h), wavelength_m) : 1.0;
  return f * he_shadowing(ci, sigma, tau, errata) * he_shadowing(co, sigma, tau, errata) * d /
         (4 * ci * co);
}

}  // namespace microbrdf
