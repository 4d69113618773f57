// Synthetic surfaces shared by several test files.
#pragma once

#include <cstddef>
#include <cstdint>

#include "microbrdf/generate.hpp"

namespace microbrdf::test_util {

/// Isotropic Gaussian surface: nx x ny samples at spacing dx, rms height sigma, correlation
/// length tau (all m), generated from `seed`.
inline Surface isotropic_gaussian(std::size_t nx, std::size_t ny, double dx, double sigma,
                                  double tau, std::uint64_t seed = GaussianSurfaceParams{}.seed) {
  GaussianSurfaceParams p;
  p.nx = nx;
  p.ny = ny;
  p.dx = p.dy = dx;
  p.sigma = sigma;
  p.tau_x = p.tau_y = tau;
  p.seed = seed;
  return generate_gaussian(p);
}

/// The same, n x n.
inline Surface isotropic_gaussian(std::size_t n, double dx, double sigma, double tau,
                                  std::uint64_t seed = GaussianSurfaceParams{}.seed) {
  return isotropic_gaussian(n, n, dx, sigma, tau, seed);
}

}  // namespace microbrdf::test_util
