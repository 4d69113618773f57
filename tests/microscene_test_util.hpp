// Micro-scenes shared by the simulation tests and benchmarks: a Gaussian height field with an
// ideal mirror material (F = 1), the surface of Westin 1992 Fig. 6 at sigma 10 um, tau 65 um.
#pragma once

#include <cstddef>
#include <cstdint>

#include "microbrdf/generate.hpp"
#include "microbrdf/microscene.hpp"
#include "surface_test_util.hpp"

namespace microbrdf::test_util {

/// An ideal diffuse material of the given albedo.
inline MicroMaterial lambert_material(double albedo) {
  MicroMaterial m;
  m.kind = MicroMaterial::Kind::Lambert;
  m.albedo = albedo;
  return m;
}

inline MicroMaterial mirror_material() {
  MicroMaterial m;
  m.kind = MicroMaterial::Kind::Mirror;
  m.name = "mirror";
  return m;
}

/// Description of one tile of an isotropic Gaussian surface (n x n samples at spacing dx, rms
/// height sigma, correlation length tau, all m; generate_gaussian's seed) with the mirror material;
/// `grid` selects the micro-scene's grid acceleration for the height field.
inline MicroSceneDesc gaussian_mirror_desc(std::size_t n, double dx, double sigma, double tau,
                                           std::uint64_t seed = GaussianSurfaceParams{}.seed,
                                           bool grid = false) {
  MicroSceneDesc d;
  d.width = d.height = n * dx;
  d.materials.push_back(mirror_material());
  d.heightfields.push_back({isotropic_gaussian(n, dx, sigma, tau, seed), 0, grid});
  return d;
}

}  // namespace microbrdf::test_util
