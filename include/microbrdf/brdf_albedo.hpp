#pragma once
// Directional albedo of any BRDF by quadrature or by its own sampler.

#include "microbrdf/brdf.hpp"

namespace microbrdf {

/// Directional albedo a(wi) = integral f(wi, wo) cos(theta_o) dwo by product quadrature:
/// Gauss-Legendre in cos(theta_o) (n_theta nodes) times the midpoint rule in phi_o (n_phi).
/// Accurate for lobes wider than a few grid steps (alpha >~ 0.05 at the defaults).
double directional_albedo(const Brdf& brdf, const Vec3& wi, double wavelength_m, int n_theta = 128,
                          int n_phi = 256);
/// The same estimated with the BRDF's own sampler on an n x n stratified grid (any lobe width).
double directional_albedo_sampled(const Brdf& brdf, const Vec3& wi, double wavelength_m,
                                  int n = 512);

}  // namespace microbrdf
