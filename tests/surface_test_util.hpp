// Synthetic surfaces shared by several test files.
#pragma once

#include <cstddef>
#include <cstdint>

#include "microbrdf/generate.hpp"

namespace microbrdf::test_util {

/// Isotropic Gaussian surface: n x n samples at spacing dx, rms height sigma, correlation
/// length tau (all m), generated from `seed`.
inline Surface isotropic_gaussian(std::size_t n, double dx, double sigma, double tau,
                                  std::uint64_t seed = GaussianSurfaceParams{}.seed) {
  GaussianSurfaceParams p;
  p.nx = p.ny = n;
  p.dx = p.dy = dx;
  p.sigma = sigma;
  p.tau_x = p.tau_y = tau;
  p.seed = seed;
  return generate_gaussian(p);
}

}  // namespace microbrdf::test_util
