// Direct light by resampled importance sampling (see direct_ris.hpp).
#include "render/direct_ris.hpp"

#include <cmath>
#include <limits>

namespace microbrdf::pt {
namespace {

constexpr double kPhi = 0.6180339887498949;  // golden-ratio fraction: the lattice's 2nd axis

/// The point (u1 + j / count, u2 + j phi) mod 1 of the shifted lattice (j may be negative).
void lattice_point(double u1, double u2, int j, int count, double& v1, double& v2) {
  const double o1 = double(j) / count, o2 = j * kPhi;
  v1 = u1 + (o1 - std::floor(o1));
  v2 = u2 + (o2 - std::floor(o2));
  if (v1 >= 1) v1 -= 1;
  if (v2 >= 1) v2 -= 1;
  v1 = std::min(v1, 0x1.fffffffffffffp-1);  // (rounding of the sums)
  v2 = std::min(v2, 0x1.fffffffffffffp-1);
}

/// Rec. 709 luminance of linear sRGB: > 0 wherever any channel is (map pixels are >= 0).
double luminance(const V3& rgb) { return 0.2126 * rgb.x() + 0.7152 * rgb.y() + 0.0722 * rgb.z(); }

struct Candidate {
  V3 wl;            // local direction (towards the light)
  V3 dir;           // world direction
  V3 rgb;           // radiance arriving without visibility
  double distance;  // to the emitter (infinity: the environment)
  double target;    // p_hat
  double weight;    // p_hat / (M p_b + N p_l)
};

}  // namespace

void ris_prefetch_light_candidates(const LightSet& lights, double u1, double u2, int N) {
  for (int j = 0; j < N; ++j) {
    double v1 = u1, v2 = u2;
    if (j > 0) lattice_point(u1, u2, j, N, v1, v2);
    lights.prefetch_sample(v1, v2, true);
  }
}

int ris_direct_light(const RisDirectInput& in, const SpectralMaterial::Sample* continuation,
                     double brdf_u1, double brdf_u2, double light_u1, double light_u2,
                     double u_select, const double* T, double* L, RisPending* pending) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const int M = in.brdf_candidates, N = in.light_candidates;
  const int n = in.wavelengths.n;
  const ShadingPoint& sp = in.sp;
  int rays = 0;
  Candidate cand[kMaxRisBrdfCandidates + kMaxRisLightCandidates];
  int count = 0;
  double sum = 0;
  auto add_spectral = [&](const V3& wl, const V3& dir, double distance, const V3& rgb, double scale,
                          RisPending* defer) {
    double f[kMaxWavelengths];
    if (!in.mat.eval(sp.u, sp.v, in.view, wl, in.wavelengths, f, nullptr)) return;
    const double tmax = std::isinf(distance) ? 1e30 : distance * (1 - 1e-6);
    const double s = scale * wl.z();
    if (defer) {
      defer->active = true;
      defer->tmax = tmax;
      for (int k = 0; k < n; ++k)
        defer->value[k] = f[k] != 0 ? T[k] * f[k] * s * rgb.dot(in.basis.col(k)) : 0.0;
      return;
    }
    ++rays;
    if (in.geo.occluded(in.origin, dir, tmax)) return;
    for (int k = 0; k < n; ++k)
      if (f[k] != 0) L[k] += T[k] * f[k] * s * rgb.dot(in.basis.col(k));
  };

  // BRDF candidates: directions first (prefetching their map pixels), then the radiance.
  // Candidate k sits at (r + k / M, u2 + (k - a) phi) mod 1 with a = floor(M u1), r = u1 - a / M:
  // candidate a is the continuation's point (u1, u2) itself, and a, uniform and independent of
  // the set of candidates, picks the stratum of the choice below.
  const int a = std::min(int(brdf_u1 * M), M - 1);
  const bool area = in.lights.has_area();
  const int first_brdf = 0;
  int pick_continuation = -1;  // the candidate that is the continuation's direction
  std::pair<int, int> pixel[kMaxRisBrdfCandidates];
  double pb[kMaxRisBrdfCandidates];
  V3 lwl[kMaxRisBrdfCandidates];
  double lpdf[kMaxRisBrdfCandidates], ltarget[kMaxRisBrdfCandidates];
  bool lok[kMaxRisBrdfCandidates];
  in.mat.lattice_directions(sp.u, sp.v, in.view, brdf_u1, brdf_u2, in.wavelengths, M, a, lwl, lpdf,
                            ltarget, lok);
  if (continuation && !continuation->delta) {
    lok[a] = true;
    lwl[a] = continuation->wo;
    lpdf[a] = continuation->pdf;
    ltarget[a] = continuation->target;
  }
  for (int j = 0; j < M; ++j) {
    if (!lok[j]) continue;
    const V3& wl = lwl[j];
    const double pdf = lpdf[j], target = ltarget[j];
    // (the continuation's direction exactly as trace_path computes it; the others are unit
    // vectors in an orthonormal frame already)
    const V3 dir = j == a ? sp.to_world(wl).normalized() : sp.to_world(wl);
    if (!(dir.dot(sp.ng) > 0)) continue;
    if (j == a) pick_continuation = count;
    Candidate& c = cand[count];
    pixel[count - first_brdf] = in.lights.prefetch_env(dir);
    pb[count - first_brdf] = pdf;
    c.wl = wl;
    c.dir = dir;
    c.target = target;
    ++count;
  }
  const int brdf_count = count;

  // Light candidates (and the delta-light samples, which are estimated on their own).
  for (int j = 0; j < N; ++j) {
    double v1 = light_u1, v2 = light_u2;
    if (j > 0) lattice_point(light_u1, light_u2, j, N, v1, v2);
    const auto ls = in.lights.sample(in.origin, v1, v2);
    if (!ls) continue;
    const V3 wl = sp.to_local(ls->dir);
    if (!(wl.z() > 0) || !(ls->dir.dot(sp.ng) > 0)) continue;
    if (ls->delta) {
      add_spectral(wl, ls->dir, ls->distance, ls->rgb, 1.0 / (N * ls->pdf), nullptr);
      continue;
    }
    const double tmax = std::isinf(ls->distance) ? 1e30 : ls->distance * (1 - 1e-6);
    if (area && in.lights.hit_area(in.origin, ls->dir, tmax).t > 0) continue;  // one in front
    double pb, target;
    if (!in.mat.ris_terms(sp.u, sp.v, in.view, wl, in.wavelengths, pb, target)) continue;
    const double p_hat = target * luminance(ls->rgb);
    if (!(p_hat > 0)) continue;
    Candidate& c = cand[count++];
    c.wl = wl;
    c.dir = ls->dir;
    c.rgb = ls->rgb;
    c.distance = ls->distance;
    c.target = p_hat;
    c.weight = p_hat / (M * pb + N * ls->pdf);
    sum += c.weight;
  }

  // (the light candidates above give the map records time to arrive)
  for (int i = first_brdf; i < brdf_count; ++i) {
    Candidate& c = cand[i];
    const LightHit lh = area ? in.lights.hit_area(in.origin, c.dir, 1e30) : LightHit{};
    double pl;
    if (lh.t > 0) {
      c.rgb = lh.rgb;
      c.distance = lh.t;
      pl = lh.pdf;
    } else {
      c.rgb = in.lights.env_rgb(c.dir, pixel[i - first_brdf], pl);
      c.distance = kInf;
    }
    c.target *= luminance(c.rgb);
    c.weight = c.target > 0 ? c.target / (M * pb[i - first_brdf] + N * pl) : 0.0;
    sum += c.weight;
  }

  if (!(sum > 0) || !std::isfinite(sum)) return rays;

  // The choice: the first candidate (BRDF candidates in the order of k, then the light ones)
  // whose running sum exceeds (a + u_select) / M * sum. (a + u_select) / M is uniform and
  // independent of the candidates, as the choice needs; when the weights are about equal it
  // picks candidate a, the continuation, so that the shadow ray keeps the stratification of
  // (u1, u2) and tests the direction whose indirect light the continuation gathers.
  const double r = (a + u_select) / M * sum;
  int pick = -1;
  double run = 0;
  for (int i = 0; i < count; ++i) {
    if (!(cand[i].weight > 0)) continue;
    pick = i;
    run += cand[i].weight;
    if (r < run) break;
  }
  const Candidate& c = cand[pick];
  add_spectral(c.wl, c.dir, c.distance, c.rgb, sum / c.target,
               pick == pick_continuation ? pending : nullptr);
  return rays;
}

}  // namespace microbrdf::pt
