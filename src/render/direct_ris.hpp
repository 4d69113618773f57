#pragma once
// Direct light by resampled importance sampling (RenderOptions::direct = DirectLight::Ris;
// Talbot, Cline and Egbert 2005, "Importance resampling for global illumination", with the
// candidates drawn from two techniques and weighted by the balance heuristic).
//
// At a shading point, M directions are drawn by BRDF sampling (density p_b) and N by light
// sampling (p_l, the nearest emitter's density including the choice of the light), without
// rays. Each candidate z gets the weight
//     w(z) = p_hat(z) / (M p_b(z) + N p_l(z)),
// with the target p_hat = D(h) / (4 sigma+(wv)) times the luminance of the radiance arriving
// from z without visibility (the emitter a ray along z meets first; a cheap stand-in for f cos L,
// positive wherever f cos L can be non-zero). One candidate z* is chosen with probability
// w(z*) / sum w, one shadow ray is traced towards it, and
//     F(z*) V(z*) / p_hat(z*) * sum w
// is added, F = f cos L at every hero wavelength. Given the candidates, this is an unbiased
// random choice of one term of the multi-sample balance-heuristic estimator
// sum_z F(z) V(z) / (M p_b(z) + N p_l(z)), which is itself unbiased as long as each candidate
// has its technique's density on its own: correlation between candidates does not matter.
// That allows the M BRDF candidates to come from one 2D point (u1, u2) shifted by the lattice
// (j / M, frac(j phi)), j = 0..M-1 (each shifted point is uniform again; together they stratify
// the lobe), and likewise the N light candidates; candidate 0 of the BRDF is the path's
// continuation (its marginal density is p_b, so the continuation stays an unbiased estimate of
// the indirect light; the caller drops the emission that continuation meets, which the
// candidates already account for).
//
// Light samples of delta lights (points) are not candidates: each adds its own shadowed
// estimate f cos I / (d^2 N P(choose)). Light candidates with another area light in front are
// refused, as BRDF-sampled rays see the nearest emitter only (the light technique's density
// is then that of the nearest emitter, the one p_l gives for BRDF candidates).

#include <Eigen/Core>

#include "render/lights.hpp"
#include "render/material.hpp"
#include "render/scene.hpp"

namespace microbrdf::pt {

inline constexpr int kMaxRisBrdfCandidates = 16;
inline constexpr int kMaxRisLightCandidates = 4;

struct RisDirectInput {
  const PreviewGeometry& geo;
  const LightSet& lights;
  const SpectralMaterial& mat;  ///< must be on the fast path (SpectralMaterial::fast())
  const SpectralMaterial::View& view;
  const SpectralMaterial::Wavelengths& wavelengths;
  const ShadingPoint& sp;
  const V3& origin;  ///< the offset shading point rays start from
  /// RGB -> spectral value at each hero wavelength (column k: wavelength k).
  const Eigen::Matrix<double, 3, kMaxWavelengths>& basis;
  int brdf_candidates = 4, light_candidates = 1;
};

/// Memory prefetches for the light candidates of the light sample's point (u1, u2), to be
/// called before the bounce's ray is traced (no effect on results).
void ris_prefetch_light_candidates(const LightSet& lights, double u1, double u2, int N);

/// Direct light whose visibility is that of the path's continuation ray (the chosen candidate
/// was the continuation's direction): the caller adds `value` to L when that ray, traced from
/// the same origin, meets no geometry closer than `tmax`, or calls resolve_by_shadow_ray() if
/// the path ends before tracing it.
struct RisPending {
  bool active = false;
  double tmax = 0;
  double value[kMaxWavelengths];
  /// With the continuation's hit distance t (-1: none).
  void resolve(double t, int n, double* L) {
    if (!active) return;
    active = false;
    if (t < 0 || t >= float(tmax))
      for (int k = 0; k < n; ++k) L[k] += value[k];
  }
  /// Returns the number of rays traced (0 or 1).
  int resolve_by_shadow_ray(const PreviewGeometry& geo, const V3& origin, const V3& dir, int n,
                            double* L) {
    if (!active) return 0;
    active = false;
    if (!geo.occluded(origin, dir, tmax))
      for (int k = 0; k < n; ++k) L[k] += value[k];
    return 1;
  }
};

/// Adds the direct light at the shading point, times the path throughput T, to L (n = the
/// wavelengths' count). `continuation`: the path's BRDF sample drawn from (brdf_u1, brdf_u2), or
/// null when that draw was refused; (light_u1, light_u2): the light sample's point; u_select:
/// the choice among the candidates. When the choice is the continuation's direction and
/// `pending` is given, no shadow ray is traced: the light goes to *pending. Returns the number
/// of shadow rays traced.
int ris_direct_light(const RisDirectInput& in, const SpectralMaterial::Sample* continuation,
                     double brdf_u1, double brdf_u2, double light_u1, double light_u2,
                     double u_select, const double* T, double* L, RisPending* pending);

}  // namespace microbrdf::pt
