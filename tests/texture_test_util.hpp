// Random parameter textures shared by the texture tests and benchmarks.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>

#include "microbrdf/generate.hpp"
#include "microbrdf/texture.hpp"

namespace microbrdf::test_util {

/// A 53 um-texel ParamTexture, all valid, whose five channels (alpha_x, alpha_y, theta_x,
/// theta_y, theta_z) are realistic brushed-metal means plus smooth Gaussian random fields of rms
/// sd[c] and Gaussian ACF with correlation lengths tau_x, tau_y (texels); channel c uses seed
/// first_seed + c and the generator's exact_spectrum choice.
inline ParamTexture gaussian_param_texture(std::size_t nx, std::size_t ny, double tau_x,
                                           double tau_y, const std::array<double, 5>& sd,
                                           std::uint64_t first_seed, bool exact_spectrum) {
  ParamTexture t = ParamTexture::empty(nx, ny, 53e-6, "");
  std::fill(t.valid.begin(), t.valid.end(), 1);
  const double mean[5] = {0.007, 0.14, 0.0, 0.0, 0.0};
  for (int c = 0; c < 5; ++c) {
    GaussianSurfaceParams g;
    g.nx = nx;
    g.ny = ny;
    // Texel units as micrometres (the generator takes lengths of a micro-surface, at most
    // 1 m): only tau / dx shapes the spectrum, so the channel is the same at any scale.
    g.dx = g.dy = 1e-6;
    g.sigma = sd[static_cast<std::size_t>(c)];
    g.tau_x = tau_x * 1e-6;
    g.tau_y = tau_y * 1e-6;
    g.seed = first_seed + static_cast<std::uint64_t>(c);
    g.exact_spectrum = exact_spectrum;
    const Surface s = generate_gaussian(g);
    for (std::size_t i = 0; i < t.size(); ++i)
      t.channel[static_cast<std::size_t>(c)][i] = static_cast<float>(mean[c] + s.z[i]);
  }
  return t;
}

}  // namespace microbrdf::test_util
