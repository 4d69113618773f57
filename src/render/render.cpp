// The spectral path tracer (render.hpp).
//
// Per pixel sample: a camera ray with a box-filter jitter, `wavelengths` hero wavelengths
// (spectral.hpp) carried together, next-event estimation from one uniformly chosen light and a
// BRDF-sampled continuation, combined by the power heuristic (MisMode::Mis; or, with
// DirectLight::Ris, direct light by resampling, direct_ris.hpp) or used alone
// (light_only: emission reached by BRDF sampling is dropped except after a delta bounce;
// brdf_only: no light samples, point lights are invisible). The BRDF's sampler is driven by the
// first (hero) wavelength; its pdf does not depend on wavelength (Brdf::pdf), so every
// wavelength is weighted by f(l_k) cos / pdf. Samples from a delta lobe (BrdfSample::delta)
// take, per wavelength, the weight its own sample() gives for the same random numbers.
// The BRDF is evaluated as f(wi = light, wo = viewer) in the local frame of the shading point.
//
// Random numbers: one PathSampler per (pixel, sample) (path_sampler.hpp), asked in a fixed order
// per path: jitter (2D), hero wavelength (1D), then per bounce the light sample (2D), the BRDF
// sample (2D), with DirectLight::Ris the choice among the candidates (1D), and, after three
// bounces, Russian roulette (1D). With the Sobol sampler each of
// these requests is stratified over the samples of a pixel.
//
// Determinism: the numbers of each (pixel, sample) are a function of (seed, pixel, sample) and
// the samples of a pixel are summed in order by one thread, so an image does not depend on the
// number of threads.
#include "microbrdf/render.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <sstream>

#include "microbrdf/error.hpp"
#include "microbrdf/memory_budget.hpp"
#include "microbrdf/microscene.hpp"
#include "microbrdf/spectrum.hpp"
#include "microbrdf/threads.hpp"
#include "render/direct_ris.hpp"
#include "render/lights.hpp"
#include "render/material.hpp"
#include "render/path_sampler.hpp"
#include "render/scene.hpp"
#include "render/spectral.hpp"

namespace microbrdf {
namespace {

using pt::V3;

double power_heuristic(double a, double b) {
  const double a2 = a * a, b2 = b * b;
  return a2 + b2 > 0 ? a2 / (a2 + b2) : 0.0;
}

/// Most light sets render_light_sets takes.
constexpr int kMaxSets = kMaxRenderLightSets;

struct PathContext {
  const pt::PreviewGeometry& geo;
  /// The light sets (one world each; the first is the render's own lights). With several, none
  /// has area lights (render_light_sets), so a ray never ends on an emitter in one set only.
  const pt::LightSet* sets;
  int nl;
  /// Per variant, its materials (one, or one per object).
  const std::vector<std::vector<pt::SpectralMaterial>>& variants;
  const RenderOptions& opt;
  const pt::SpectralTables& spec;
  const double* mix_weight;  ///< per variant, its share of the BRDF-sampling mixture
  const double* mix_cdf;     ///< running sums of mix_weight (the last is 1)
  bool ris;                  ///< direct light by resampling (direct_light_used)
  bool dark;                 ///< no set has environment light: an escaping ray carries nothing
};

/// The direct-light estimator a render really uses (trace_path and the settings line): resampled
/// direct light (direct_ris.hpp) needs one variant and one light set (otherwise the light
/// samples are shared by several MIS estimators), --mis mis, and a light other than a uniform
/// environment alone (whose target would be the BRDF's own density: resampling would cost
/// without lowering the noise).
DirectLight direct_light_used(const RenderOptions& opt, const pt::LightSet& lights, int variants,
                              int light_sets) {
  const bool uniform_env_only = lights.count() == 1 && lights.env() && lights.env()->is_uniform();
  return variants == 1 && light_sets == 1 && opt.direct == DirectLight::Ris &&
                 opt.mis == MisMode::Mis && !uniform_env_only
             ? DirectLight::Ris
             : DirectLight::Mis;
}

/// What a path's hero wavelengths fix: the upsampling basis at each (RGB lights -> spectrum)
/// and, per variant and material, its optical constants (SpectralMaterial::prepare, done on
/// first use).
struct PathSpectrum {
  int n = 0;
  double lambda_m[pt::kMaxWavelengths];
  Eigen::Matrix<double, 3, pt::kMaxWavelengths> basis;  // (uninitialised: the first n are set)
  pt::SpectralMaterial::Wavelengths mat[kMaxRenderVariants][2];
  bool prepared[kMaxRenderVariants][2] = {};
  double upsample(const V3& rgb, int k) const { return rgb.dot(basis.col(k)); }
};

using Radiance = double[kMaxRenderVariants][pt::kMaxWavelengths];

/// Radiance (relative to D65) at the n hero wavelengths along one camera path, added to
/// L[l][v] for each light set l and variant v. With one variant and one light set this is the
/// plain path tracer; with several variants, the geometry, the light samples and the shadow rays
/// are shared, and each BRDF-sampled direction comes from the mixture of the variants' samplers
/// (render_variants); with several light sets, the path is shared and each set has its own light
/// samples, shadow rays and emission (render_light_sets).
std::uint64_t trace_path(const PathContext& c, V3 o, V3 d, PathSpectrum& ps, pt::PathSampler& rng,
                         Radiance* L) {
  const int n = ps.n;
  const int nv = static_cast<int>(c.variants.size());
  const int nl = c.nl;
  const pt::LightSet& lights0 = c.sets[0];
  double T[kMaxRenderVariants][pt::kMaxWavelengths];
  for (int v = 0; v < nv; ++v)
    for (int k = 0; k < n; ++k) T[v][k] = 1;
  std::uint64_t rays = 0;
  bool specular = true;  // camera ray or a delta bounce: emission counts fully
  double prev_pdf = 0;   // BRDF-sampling (mixture) density of the current ray direction
  // The first variant's part of it, w_0 p_0: the BRDF density in the MIS weights of the light
  // sets after the first, which light the first variant only (render_light_sets).
  double prev_q = 0;
  const bool use_nee = c.opt.mis != MisMode::BrdfOnly;
  const bool use_brdf_emission = c.opt.mis != MisMode::LightOnly;
  // Resampled direct light where the material allows (direct_light_used); its continuation then
  // carries indirect light only: emission it meets is already counted.
  const bool use_ris = c.ris;
  bool after_ris = false;
  pt::RisPending pending;  // direct light whose visibility is the continuation ray's
  auto add_emission = [&](int l, const V3& rgb, double light_pdf) {
    double w = 1;
    if (!specular) {
      if (!use_brdf_emission || after_ris) return;
      // (a direction the light cannot draw is the BRDF technique's alone: weight 1, also
      // where a further set's w_0 p_0 is 0 there)
      if (use_nee && light_pdf > 0) w = power_heuristic(l == 0 ? prev_pdf : prev_q, light_pdf);
    }
    if (!(w > 0)) return;
    double e[pt::kMaxWavelengths];  // (once for every variant)
    for (int k = 0; k < n; ++k) e[k] = ps.upsample(rgb, k);
    for (int v = 0; v < (l == 0 ? nv : 1); ++v)
      for (int k = 0; k < n; ++k) L[l][v][k] += T[v][k] * w * e[k];
  };

  pt::ShadingPoint next_sp;  // the next ray's hit when it was traced early (have_next)
  double next_t = -1;
  bool have_next = false;
  const pt::SpectralMaterial* mat[kMaxRenderVariants];
  pt::SpectralMaterial::Wavelengths* wl_consts[kMaxRenderVariants];
  pt::SpectralMaterial::View view[kMaxRenderVariants];
  for (int depth = 0;; ++depth) {
    // The light sample's numbers are drawn before the ray is traced (the same request order):
    // the environment map's tables and the radiance this ray meets if it escapes are then
    // loaded from memory while Embree works.
    // (each light set its own numbers, drawn in set order: one set keeps the request order)
    double nee_u[kMaxSets][2] = {};
    const bool nee = use_nee && lights0.count() > 0;
    if (nee)
      for (int l = 0; l < nl; ++l) {
        rng.get2d(nee_u[l][0], nee_u[l][1]);
        if (use_ris)
          pt::ris_prefetch_light_candidates(c.sets[l], nee_u[l][0], nee_u[l][1],
                                            c.opt.ris_light_candidates);
        else
          c.sets[l].prefetch_sample(nee_u[l][0], nee_u[l][1]);
      }
    std::pair<int, int> env_pixel[kMaxSets];
    for (int l = 0; l < nl; ++l)
      env_pixel[l] = after_ris ? std::pair<int, int>{-1, -1} : c.sets[l].prefetch_env(d);
    pt::ShadingPoint sp;
    double t;
    if (have_next) {  // (traced before the throughputs were updated, below)
      sp = next_sp;
      t = next_t;
      have_next = false;
    } else {
      ++rays;
      t = c.geo.intersect(o, d, 1e30, sp);
    }
    pending.resolve(t, n, L[0][0]);
    const pt::LightHit lh = lights0.hit_area(o, d, t > 0 ? t : 1e30);  // (one set only)
    if (lh.t > 0) {
      add_emission(0, lh.rgb, lh.pdf);
      return rays;
    }
    if (t < 0) {
      if (after_ris) return rays;
      for (int l = 0; l < nl; ++l) {
        double pdf;
        const V3 rgb = c.sets[l].env_rgb(d, env_pixel[l], pdf);
        if (c.sets[l].env()) add_emission(l, rgb, pdf);
      }
      return rays;
    }
    if (depth >= c.opt.max_depth) return rays;
    const V3 wv = sp.to_local(-d);  // towards the viewer
    if (!(wv.z() > 0)) return rays;
    for (int v = 0; v < nv; ++v) {
      const auto& mats = c.variants[v];
      const int slot = mats.size() == 1 ? 0 : std::min(sp.object, 1);
      mat[v] = &mats[mats.size() == 1 ? 0 : sp.object];
      // Variants whose metals are the same object share their wavelength constants; otherwise
      // the material's own, once per path and material (the cylinder pair may have two
      // materials; with more than two, every bounce prepares its own).
      int same = 0;
      while (same < v && mat[same]->wavelength_key() != mat[v]->wavelength_key()) ++same;
      if (same < v) {
        wl_consts[v] = wl_consts[same];
      } else {
        wl_consts[v] = &ps.mat[v][slot];
        if (!ps.prepared[v][slot] || mats.size() > 2) {
          mat[v]->prepare(ps.lambda_m, n, *wl_consts[v]);
          ps.prepared[v][slot] = mats.size() <= 2;
        }
      }
      view[v] = mat[v]->view(wv);
    }
    const V3 origin = sp.p + sp.eps * sp.ng;  // (a micro-scene's hits: its own offset)

    // Next-event estimation, per light set: the first set for every variant, the others for
    // the first variant only.
    const bool ris = use_ris && nee;
    for (int l = 0; nee && !ris && l < nl; ++l) {
      if (auto ls = c.sets[l].sample(origin, nee_u[l][0], nee_u[l][1])) {
        const V3 wl = sp.to_local(ls->dir);
        if (wl.z() > 0 && ls->dir.dot(sp.ng) > 0) {
          // f and the BRDF density before the shadow ray: no ray for a light sample the BRDF
          // does not reflect.
          double f[kMaxRenderVariants][pt::kMaxWavelengths], pdf[kMaxRenderVariants];
          bool reflects[kMaxRenderVariants], any = false;
          const bool mis = !ls->delta && c.opt.mis == MisMode::Mis;
          const int lit = l == 0 ? nv : 1;  // the variants this set lights
          for (int v = 0; v < lit; ++v) {
            pdf[v] = 0;
            // (a variant that never draws needs no density)
            reflects[v] = mat[v]->eval(sp.u, sp.v, view[v], wl, *wl_consts[v], f[v],
                                       mis && c.mix_weight[v] > 0 ? &pdf[v] : nullptr);
            any |= reflects[v];
          }
          if (any) {
            // The BRDF technique's density here: with variants, the mixture's, which needs
            // every sampler's density, also where its own f is 0.
            // The other sets weigh their light sample against w_0 p_0 alone (prev_q): they
            // need no other variant's density, and the weights of the two techniques still
            // sum to 1 wherever the first variant's sampler or the light's can draw.
            double brdf_pdf = l == 0 ? pdf[0] : c.mix_weight[0] * pdf[0];
            if (l == 0 && nv > 1 && mis) {
              brdf_pdf = 0;
              for (int v = 0; v < nv; ++v)
                if (c.mix_weight[v] > 0)
                  brdf_pdf +=
                      c.mix_weight[v] *
                      (reflects[v] ? pdf[v] : mat[v]->sampling_pdf(sp.u, sp.v, view[v], wl));
            }
            ++rays;
            // Blocked by geometry, or by another area light in front (the same rule as for
            // BRDF-sampled rays, which see the nearest emitter only).
            const double tmax = std::isinf(ls->distance) ? 1e30 : ls->distance * (1 - 1e-6);
            if (!c.geo.occluded(origin, ls->dir, tmax) &&
                !(c.sets[l].hit_area(origin, ls->dir, tmax).t > 0)) {
              const double w = mis ? power_heuristic(ls->pdf, brdf_pdf) : 1.0;
              const double scale = w * wl.z() / ls->pdf;
              double e[pt::kMaxWavelengths];  // (once for every variant)
              for (int k = 0; k < n; ++k) e[k] = ps.upsample(ls->rgb, k);
              for (int v = 0; v < lit; ++v)
                if (reflects[v])
                  for (int k = 0; k < n; ++k)
                    if (f[v][k] != 0) L[l][v][k] += T[v][k] * f[v][k] * scale * e[k];
            }
          }
        }
      }
    }

    // BRDF sampling (the viewer direction plays wi; see the header comment).
    double u1, u2;
    rng.get2d(u1, u2);
    int pick = 0;
    if (nv > 1) {
      // Which variant's sampler draws: u1 chooses by the mixture weights and, stretched back
      // to [0, 1), drives the sample (as LightSet::sample does with the light choice).
      while (pick < nv - 1 && !(u1 < c.mix_cdf[pick])) ++pick;
      const double lo = pick == 0 ? 0.0 : c.mix_cdf[pick - 1];
      u1 = std::min((u1 - lo) / c.mix_weight[pick], std::nextafter(1.0, 0.0));
    }
    pt::SpectralMaterial::Sample s;
    const bool sampled = mat[pick]->sample(sp.u, sp.v, view[pick], u1, u2, *wl_consts[pick], s);
    if (ris) {  // (one variant: use_ris)
      const pt::RisDirectInput in{c.geo,
                                  lights0,
                                  *mat[0],
                                  view[0],
                                  *wl_consts[0],
                                  sp,
                                  origin,
                                  ps.basis,
                                  c.opt.ris_brdf_candidates,
                                  c.opt.ris_light_candidates};
      rays += pt::ris_direct_light(in, sampled ? &s : nullptr, u1, u2, nee_u[0][0], nee_u[0][1],
                                   rng.get1d(), T[0], L[0][0], &pending);
    }
    if (!sampled) return rays;
    after_ris = ris && !s.delta;
    const V3 wl = s.wo;
    const V3 next_d = sp.to_world(wl).normalized();
    if (next_d.dot(sp.ng) <= 0) return rays;  // below the geometric surface
    if (nv == 1) {
      for (int k = 0; k < n; ++k) T[0][k] *= s.weight[k];
      prev_pdf = prev_q = s.pdf;
    } else if (s.delta) {
      // A delta lobe carries only the variant that drew it, chosen with its mixture weight.
      for (int v = 0; v < nv; ++v)
        for (int k = 0; k < n; ++k)
          T[v][k] = v == pick ? T[v][k] * s.weight[k] / c.mix_weight[pick] : 0.0;
      prev_pdf = prev_q = 0;
    } else {
      // Without environment light a direction that meets neither geometry nor an area light
      // carries nothing further (most continuations off the plate under its small light):
      // trace it first, and only then pay for the other variants' BRDF values. The hit is kept
      // for the next bounce, so the images are the same.
      if (c.dark) {
        ++rays;
        next_t = c.geo.intersect(origin, next_d, 1e30, next_sp);
        if (next_t < 0 && !(lights0.hit_area(origin, next_d, 1e30).t > 0)) return rays;
        have_next = true;
      }
      // f_v cos / p_mix for every variant, p_mix = sum_v w_v p_v(wl): the density with which
      // the mixture drew wl (the drawing sampler's own f cos is its weight times its pdf).
      double fc[kMaxRenderVariants][pt::kMaxWavelengths], p_mix = 0;
      prev_q = 0;
      for (int v = 0; v < nv; ++v) {
        if (v == pick) {
          p_mix += c.mix_weight[v] * s.pdf;
          if (v == 0) prev_q = c.mix_weight[0] * s.pdf;
          for (int k = 0; k < n; ++k) fc[v][k] = s.weight[k] * s.pdf;
          continue;
        }
        double p = 0;
        const bool draws = c.mix_weight[v] > 0;
        if (!mat[v]->eval(sp.u, sp.v, view[v], wl, *wl_consts[v], fc[v], draws ? &p : nullptr) &&
            draws)
          p = mat[v]->sampling_pdf(sp.u, sp.v, view[v], wl);
        p_mix += c.mix_weight[v] * p;
        if (v == 0) prev_q = c.mix_weight[0] * p;
        for (int k = 0; k < n; ++k) fc[v][k] *= wl.z();
      }
      if (!(p_mix > 0 && std::isfinite(p_mix))) return rays;
      for (int v = 0; v < nv; ++v)
        for (int k = 0; k < n; ++k) T[v][k] *= fc[v][k] / p_mix;
      prev_pdf = p_mix;
    }
    specular = s.delta;
    d = next_d;
    o = origin;
    // A path that ends here traces the pending direct light's shadow ray itself.
    auto end = [&] { return rays + pending.resolve_by_shadow_ray(c.geo, o, d, n, L[0][0]); };
    // Russian roulette after three bounces (one decision for every variant).
    double tmax = 0;
    for (int v = 0; v < nv; ++v)
      for (int k = 0; k < n; ++k) {
        if (!std::isfinite(T[v][k])) return end();
        tmax = std::max(tmax, std::abs(T[v][k]));
      }
    if (!(tmax > 0)) return end();
    if (depth >= 3) {
      const double q = std::min(1.0, tmax);
      if (rng.get1d() >= q) return end();
      for (int v = 0; v < nv; ++v)
        for (int k = 0; k < n; ++k) T[v][k] /= q;
    }
  }
}

}  // namespace

RenderSampler parse_render_sampler(const std::string& name, const std::string& flag) {
  if (name == "sobol") return RenderSampler::Sobol;
  if (name == "independent") return RenderSampler::Independent;
  throw InputError(flag + " '" + name + "': give sobol or independent");
}

DirectLight parse_direct_light(const std::string& name, const std::string& flag) {
  if (name == "mis") return DirectLight::Mis;
  if (name == "ris") return DirectLight::Ris;
  throw InputError(flag + " '" + name + "': give mis or ris");
}

std::string direct_light_name(DirectLight d) { return d == DirectLight::Ris ? "ris" : "mis"; }

std::string render_sampler_name(RenderSampler s) {
  return s == RenderSampler::Sobol ? "sobol" : "independent";
}

namespace {

std::string settings_line(const RenderScene& scene,
                          const std::vector<std::shared_ptr<const Svbrdf>>& materials,
                          const RenderLights& lights, const RenderOptions& opt, int variants,
                          int light_sets, DirectLight direct) {
  std::ostringstream os;
  os << "scene " << preview_scene_name(scene.kind);
  if (scene.micro_scene)
    os << " (micro-scene " << scene.micro_scene->name << ", " << scene.micro_tiles
       << " tiles across)";
  os << "; materials:";
  for (const auto& m : materials) os << " [" << m->describe() << "]";
  os << "; lights:";
  if (lights.uniform_white_env) os << " uniform white environment";
  if (!lights.envmap_path.empty())
    os << " envmap " << lights.envmap_path << " x" << lights.envmap_scale;
  os << " points " << lights.points.size() << " spheres " << lights.spheres.size() << " disks "
     << lights.disks.size() << "; " << opt.width << "x" << opt.height << ", " << opt.spp << " spp, "
     << opt.wavelengths << " wavelengths/path, max depth " << opt.max_depth << ", seed " << opt.seed
     << ", mis "
     << (opt.mis == MisMode::Mis        ? "power"
         : opt.mis == MisMode::BrdfOnly ? "brdf_only"
                                        : "light_only")
     << ", sampler " << render_sampler_name(opt.sampler);
  os << ", direct light " << direct_light_name(direct);
  if (direct == DirectLight::Ris)
    os << " (" << opt.ris_brdf_candidates << " BRDF + " << opt.ris_light_candidates
       << " light candidates)";
  if (variants > 1) os << ", one of " << variants << " variants along shared paths";
  if (light_sets > 1) os << ", one of " << light_sets << " light sets along shared paths";
  return os.str();
}

}  // namespace

RenderImage render(const RenderScene& scene,
                   const std::vector<std::shared_ptr<const Svbrdf>>& materials,
                   const RenderLights& lights, const RenderOptions& opt) {
  RenderOptions one = opt;
  one.variant_weights.clear();
  return std::move(render_variants(scene, {materials}, lights, one).front());
}

std::vector<RenderImage> render_variants(
    const RenderScene& scene,
    const std::vector<std::vector<std::shared_ptr<const Svbrdf>>>& variants,
    const RenderLights& lights, const RenderOptions& opt) {
  return render_light_sets(scene, variants, {lights}, opt);
}

std::vector<RenderImage> render_light_sets(
    const RenderScene& scene,
    const std::vector<std::vector<std::shared_ptr<const Svbrdf>>>& variants,
    const std::vector<RenderLights>& light_sets, const RenderOptions& opt) {
  if (opt.width <= 0 || opt.height <= 0 || opt.width > 16384 || opt.height > 16384)
    throw InputError("render: image size must be 1..16384 pixels a side");
  if (opt.spp <= 0) throw InputError("render: samples per pixel must be > 0");
  {
    // Per image: linear RGB floats (and two half images), plus the 8-bit or half-float copy an
    // output writer makes (<= 8 bytes a pixel); checked before the scene is built.
    const std::uint64_t pixels = std::uint64_t(opt.width) * std::uint64_t(opt.height);
    const std::uint64_t images = variants.size() + std::max<std::size_t>(light_sets.size(), 1) - 1;
    check_memory("render", mul_sat(pixels, images * 12 * (opt.half_images ? 3 : 1) + 8),
                 "the images (" + std::to_string(opt.width) + " x " + std::to_string(opt.height) +
                     " pixels)");
  }
  if (opt.half_images && opt.spp < 2)
    throw InputError("render: half images need at least 2 samples per pixel");
  if (opt.max_depth < 1) throw InputError("render: max depth must be >= 1");
  if (opt.wavelengths < 1 || opt.wavelengths > pt::kMaxWavelengths)
    throw InputError("render: wavelengths per path must be 1..16");
  const int nv = static_cast<int>(variants.size());
  if (nv < 1 || nv > kMaxRenderVariants)
    throw InputError("render: give 1.." + std::to_string(kMaxRenderVariants) +
                     " material variants, not " + std::to_string(nv));
  // The mixture of the variants' samplers: shares normalised to 1, their running sums.
  std::vector<double> mix(nv, 1.0), cdf(nv);
  if (!opt.variant_weights.empty()) {
    if (int(opt.variant_weights.size()) != nv)
      throw InputError("render: " + std::to_string(opt.variant_weights.size()) +
                       " variant weights for " + std::to_string(nv) + " variants");
    for (int v = 0; v < nv; ++v) {
      mix[v] = opt.variant_weights[v];
      if (!(mix[v] >= 0) || !std::isfinite(mix[v]))
        throw InputError("render: variant weights must be finite and >= 0");
    }
  }
  double total = 0;
  for (double w : mix) total += w;
  if (!(total > 0)) throw InputError("render: the variant weights are all 0");
  double run = 0;
  for (int v = 0; v < nv; ++v) {
    mix[v] /= total;
    run += mix[v];
    cdf[v] = run;
  }
  cdf[nv - 1] = 1;
  if (opt.ris_brdf_candidates < 1 || opt.ris_brdf_candidates > pt::kMaxRisBrdfCandidates)
    throw InputError("render: RIS BRDF candidates must be 1..16");
  if (opt.ris_light_candidates < 1 || opt.ris_light_candidates > pt::kMaxRisLightCandidates)
    throw InputError("render: RIS light candidates must be 1..4");
  const auto t0 = std::chrono::steady_clock::now();
  pt::PreviewGeometry geo(scene);
  // Uniform materials ignore the texture coordinates.
  bool uniform = true;
  for (const auto& materials : variants) {
    if (materials.empty()) throw InputError("render: no material");
    for (const auto& m : materials) {
      if (!m) throw InputError("render: null material");
      uniform &= dynamic_cast<const UniformSvbrdf*>(m.get()) != nullptr;
    }
    if (materials.size() != 1 && int(materials.size()) != geo.object_count())
      throw InputError("render: scene '" + preview_scene_name(scene.kind) + "' has " +
                       std::to_string(geo.object_count()) + " objects; give 1 or " +
                       std::to_string(geo.object_count()) + " materials, not " +
                       std::to_string(materials.size()));
  }
  geo.set_texture_coordinates(!uniform);
  const int nl = static_cast<int>(light_sets.size());
  if (nl < 1 || nl > kMaxRenderLightSets)
    throw InputError("render: give 1.." + std::to_string(kMaxRenderLightSets) +
                     " light sets, not " + std::to_string(nl));
  std::vector<pt::LightSet> sets;
  sets.reserve(nl);
  for (int l = 0; l < nl; ++l) {
    sets.emplace_back(light_sets[l]);
    const std::string which =
        nl > 1 ? " in light set " + std::to_string(l + 1) + (l == 0 ? " (the render's own)" : "")
               : "";
    if (sets.back().count() == 0)
      throw InputError("render: no light" + which + " (give an environment map or lights)");
    // A ray that meets an area light ends there; in one set only, the other sets' paths would
    // have to go on.
    if (nl > 1 && sets.back().has_area())
      throw InputError("render: area lights (spheres, disks)" + which +
                       ": with several light sets, give environment maps and point lights only");
  }
  const pt::LightSet& ls = sets.front();
  const auto& spec = pt::SpectralTables::get();
  std::vector<std::vector<pt::SpectralMaterial>> mats(nv);
  for (int v = 0; v < nv; ++v)
    for (const auto& m : variants[v]) mats[v].emplace_back(m);
  const DirectLight direct = direct_light_used(opt, ls, nv, nl);
  bool dark = true;
  for (const auto& s : sets) dark &= s.env() == nullptr;
  const PathContext ctx{
      geo, sets.data(), nl, mats, opt, spec, mix.data(), cdf.data(), direct == DirectLight::Ris,
      dark};
  const Eigen::Matrix3d to_rgb = xyz_to_linear_srgb_matrix();

  // Every variant under the first light set, then the first variant under each other set.
  const int ni = nv + nl - 1;
  auto set_of = [nv](int i) { return i < nv ? 0 : i - nv + 1; };
  auto variant_of = [nv](int i) { return i < nv ? i : 0; };
  std::vector<RenderImage> imgs(ni);
  const std::size_t values = std::size_t(opt.width) * opt.height * 3;
  const bool halves = opt.half_images;
  for (auto& img : imgs) {
    img.width = opt.width;
    img.height = opt.height;
    img.rgb.assign(values, 0.0f);
    if (halves) {
      img.half_rgb[0].assign(values, 0.0f);
      img.half_rgb[1].assign(values, 0.0f);
    }
  }
  const pt::Camera& cam = geo.camera();
  const int n = opt.wavelengths;
  std::atomic<int> rows_done{0};
  std::uint64_t rays = 0;
  const int threads = resolve_thread_count(opt.threads);
  const auto kind = opt.sampler == RenderSampler::Sobol ? pt::PathSamplerKind::Sobol
                                                        : pt::PathSamplerKind::Independent;
  const int first_half = opt.spp / 2;  // samples [0, spp/2) and [spp/2, spp)
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads) reduction(+ : rays)
  for (int y = 0; y < opt.height; ++y) {
    for (int x = 0; x < opt.width; ++x) {
      const std::uint64_t pixel = std::uint64_t(y) * opt.width + x;
      Eigen::Vector3d xyz[kMaxSets + kMaxRenderVariants][2];
      for (int i = 0; i < ni; ++i) xyz[i][0] = xyz[i][1] = Eigen::Vector3d::Zero();
      pt::PixelHashes hashes(opt.seed, pixel);  // (shared by the pixel's samples)
      for (int s = 0; s < opt.spp; ++s) {
        pt::PathSampler rng(kind, hashes, std::uint32_t(s), std::uint32_t(opt.spp));
        double jx, jy;
        rng.get2d(jx, jy);
        double lambda[pt::kMaxWavelengths];
        Radiance L[kMaxSets];
        for (int l = 0; l < nl; ++l)
          for (int v = 0; v < nv; ++v)
            for (int k = 0; k < n; ++k) L[l][v][k] = 0;
        double lweight[pt::kMaxWavelengths];
        pt::visible_hero_wavelengths(rng.get1d(), n, lambda, lweight);
        PathSpectrum ps;
        ps.n = n;
        for (int k = 0; k < n; ++k) {
          ps.lambda_m[k] = lambda[k] * 1e-9;
          ps.basis.col(k) = spec.basis(lambda[k]);
        }
        const V3 d = cam.direction(x + jx, y + jy, opt.width, opt.height);
        rays += trace_path(ctx, cam.position, d, ps, rng, L);
        Eigen::Vector3d xyz_w[pt::kMaxWavelengths];  // (looked up once for every image)
        for (int k = 0; k < n; ++k) xyz_w[k] = spec.xyz_weight(lambda[k]);
        for (int i = 0; i < ni; ++i) {
          const double* Li = L[set_of(i)][variant_of(i)];
          Eigen::Vector3d sx = Eigen::Vector3d::Zero();
          for (int k = 0; k < n; ++k)
            if (Li[k] != 0) sx += (Li[k] * lweight[k]) * xyz_w[k];
          if (sx.allFinite()) xyz[i][s < first_half ? 0 : 1] += sx / n;
        }
      }
      for (int v = 0; v < ni; ++v) {
        RenderImage& img = imgs[v];
        const Eigen::Vector3d rgb = to_rgb * ((xyz[v][0] + xyz[v][1]) / opt.spp);
        for (int ch = 0; ch < 3; ++ch) img.rgb[pixel * 3 + ch] = float(rgb[ch]);
        if (halves)
          for (int h = 0; h < 2; ++h) {
            const int count = h == 0 ? first_half : opt.spp - first_half;
            const Eigen::Vector3d hr = to_rgb * (xyz[v][h] / count);
            for (int ch = 0; ch < 3; ++ch) img.half_rgb[h][pixel * 3 + ch] = float(hr[ch]);
          }
      }
    }
    const int done = ++rows_done;
    if (opt.progress && omp_get_thread_num() == 0) opt.progress(double(done) / opt.height);
  }
  if (opt.progress) opt.progress(1.0);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  for (int i = 0; i < ni; ++i) {
    RenderImage& img = imgs[i];
    img.seconds = seconds;
    img.samples_per_second = double(opt.width) * opt.height * opt.spp / std::max(seconds, 1e-9);
    img.rays = rays;
    img.settings =
        settings_line(scene, variants[variant_of(i)], light_sets[set_of(i)], opt, nv, nl, direct);
  }
  return imgs;
}

}  // namespace microbrdf
