// Directional albedo of any BRDF (include/microbrdf/brdf_albedo.hpp).
#include "microbrdf/brdf_albedo.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "microbrdf/quadrature.hpp"

namespace microbrdf {
namespace {
constexpr double kPi = 3.14159265358979323846;
}

double directional_albedo(const Brdf& brdf, const Vec3& wi, double wavelength_m, int n_theta,
                          int n_phi) {
  std::vector<double> x, w;
  gauss_legendre(n_theta, x, w);
  double sum = 0;
  for (int i = 0; i < n_theta; ++i) {
    const double mu = 0.5 * (x[static_cast<std::size_t>(i)] + 1);  // cos theta_o in (0, 1)
    const double st = std::sqrt(std::max(0.0, 1 - mu * mu));
    double ring = 0;
    for (int j = 0; j < n_phi; ++j) {
      const double phi = 2 * kPi * (j + 0.5) / n_phi;
      ring += brdf.eval(wi, Vec3(st * std::cos(phi), st * std::sin(phi), mu), wavelength_m);
    }
    sum += 0.5 * w[static_cast<std::size_t>(i)] * mu * ring * (2 * kPi / n_phi);
  }
  return sum;
}

double directional_albedo_sampled(const Brdf& brdf, const Vec3& wi, double wavelength_m, int n) {
  double sum = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      auto s = brdf.sample(wi, (i + 0.5) / n, (j + 0.5) / n, wavelength_m);
      if (s) sum += s->weight;
    }
  return sum / (static_cast<double>(n) * n);
}

}  // namespace microbrdf
