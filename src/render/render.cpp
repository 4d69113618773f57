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

struct PathContext {
  const pt::PreviewGeometry& geo;
  const pt::LightSet& lights;
  const std::vector<pt::SpectralMaterial>& mats;
  const RenderOptions& opt;
  const pt::SpectralTables& spec;
};

/// What a path's hero wavelengths fix: the upsampling basis at each (RGB lights -> spectrum)
/// and, per material, its optical constants (SpectralMaterial::prepare, done on first use).
struct PathSpectrum {
  int n = 0;
  double lambda_m[pt::kMaxWavelengths];
  Eigen::Matrix<double, 3, pt::kMaxWavelengths> basis;  // (uninitialised: the first n are set)
  pt::SpectralMaterial::Wavelengths mat[2];
  bool prepared[2] = {false, false};
  double upsample(const V3& rgb, int k) const { return rgb.dot(basis.col(k)); }
};

/// Radiance (relative to D65) at the n hero wavelengths along one camera path, added to L.
std::uint64_t trace_path(const PathContext& c, V3 o, V3 d, PathSpectrum& ps, pt::PathSampler& rng,
                         double* L) {
  const int n = ps.n;
  double T[pt::kMaxWavelengths];
  for (int k = 0; k < n; ++k) T[k] = 1;
  std::uint64_t rays = 0;
  bool specular = true;  // camera ray or a delta bounce: emission counts fully
  double prev_pdf = 0;   // BRDF-sampling density of the current ray direction
  const bool use_nee = c.opt.mis != MisMode::BrdfOnly;
  const bool use_brdf_emission = c.opt.mis != MisMode::LightOnly;
  // Resampled direct light (direct_ris.hpp) where the material allows; its continuation then
  // carries indirect light only: emission it meets is already counted.
  // Not under a uniform environment alone: the target is then the BRDF's own density, and
  // resampling would cost without lowering the noise.
  const bool use_ris = c.opt.direct == DirectLight::Ris && c.opt.mis == MisMode::Mis &&
                       !(c.lights.count() == 1 && c.lights.env() && c.lights.env()->is_uniform());
  bool after_ris = false;
  pt::RisPending pending;  // direct light whose visibility is the continuation ray's
  const double eps = c.geo.epsilon();
  auto add_emission = [&](const V3& rgb, double light_pdf) {
    double w = 1;
    if (!specular) {
      if (!use_brdf_emission || after_ris) return;
      if (use_nee) w = power_heuristic(prev_pdf, light_pdf);
    }
    if (!(w > 0)) return;
    for (int k = 0; k < n; ++k) L[k] += T[k] * w * ps.upsample(rgb, k);
  };

  for (int depth = 0;; ++depth) {
    // The light sample's numbers are drawn before the ray is traced (the same request order):
    // the environment map's tables and the radiance this ray meets if it escapes are then
    // loaded from memory while Embree works.
    double nee_u1 = 0, nee_u2 = 0;
    const bool nee = use_nee && c.lights.count() > 0;
    if (nee) {
      rng.get2d(nee_u1, nee_u2);
      if (use_ris)
        pt::ris_prefetch_light_candidates(c.lights, nee_u1, nee_u2, c.opt.ris_light_candidates);
      else
        c.lights.prefetch_sample(nee_u1, nee_u2);
    }
    const auto env_pixel = after_ris ? std::pair<int, int>{-1, -1} : c.lights.prefetch_env(d);
    pt::ShadingPoint sp;
    ++rays;
    const double t = c.geo.intersect(o, d, 1e30, sp);
    pending.resolve(t, n, L);
    const pt::LightHit lh = c.lights.hit_area(o, d, t > 0 ? t : 1e30);
    if (lh.t > 0) {
      add_emission(lh.rgb, lh.pdf);
      return rays;
    }
    if (t < 0) {
      if (after_ris) return rays;
      double pdf;
      const V3 rgb = c.lights.env_rgb(d, env_pixel, pdf);
      if (c.lights.env()) add_emission(rgb, pdf);
      return rays;
    }
    if (depth >= c.opt.max_depth) return rays;
    const int slot = c.mats.size() == 1 ? 0 : std::min(sp.object, 1);
    const pt::SpectralMaterial& mat = c.mats[c.mats.size() == 1 ? 0 : sp.object];
    const V3 wv = sp.to_local(-d);  // towards the viewer
    if (!(wv.z() > 0)) return rays;
    // The material's wavelength constants, once per path and material (the cylinder pair may
    // have two materials; with more than two, every bounce prepares its own).
    pt::SpectralMaterial::Wavelengths* wl_consts = &ps.mat[slot];
    if (!ps.prepared[slot] || c.mats.size() > 2) {
      mat.prepare(ps.lambda_m, n, *wl_consts);
      ps.prepared[slot] = c.mats.size() <= 2;
    }
    const pt::SpectralMaterial::View view = mat.view(wv);
    const V3 origin = sp.p + eps * sp.ng;

    // Next-event estimation.
    const bool ris = use_ris && nee;
    if (nee && !ris) {
      if (auto ls = c.lights.sample(origin, nee_u1, nee_u2)) {
        const V3 wl = sp.to_local(ls->dir);
        if (wl.z() > 0 && ls->dir.dot(sp.ng) > 0) {
          // f and the BRDF density before the shadow ray: no ray for a light sample the BRDF
          // does not reflect.
          double f[pt::kMaxWavelengths], brdf_pdf = 0;
          const bool mis = !ls->delta && c.opt.mis == MisMode::Mis;
          if (mat.eval(sp.u, sp.v, view, wl, *wl_consts, f, mis ? &brdf_pdf : nullptr)) {
            ++rays;
            // Blocked by geometry, or by another area light in front (the same rule as for
            // BRDF-sampled rays, which see the nearest emitter only).
            const double tmax = std::isinf(ls->distance) ? 1e30 : ls->distance * (1 - 1e-6);
            if (!c.geo.occluded(origin, ls->dir, tmax) &&
                !(c.lights.hit_area(origin, ls->dir, tmax).t > 0)) {
              const double w = mis ? power_heuristic(ls->pdf, brdf_pdf) : 1.0;
              const double scale = w * wl.z() / ls->pdf;
              for (int k = 0; k < n; ++k)
                if (f[k] != 0) L[k] += T[k] * f[k] * scale * ps.upsample(ls->rgb, k);
            }
          }
        }
      }
    }

    // BRDF sampling (the viewer direction plays wi; see the header comment).
    double u1, u2;
    rng.get2d(u1, u2);
    pt::SpectralMaterial::Sample s;
    const bool sampled = mat.sample(sp.u, sp.v, view, u1, u2, *wl_consts, s);
    if (ris) {
      const pt::RisDirectInput in{c.geo,
                                  c.lights,
                                  mat,
                                  view,
                                  *wl_consts,
                                  sp,
                                  origin,
                                  ps.basis,
                                  c.opt.ris_brdf_candidates,
                                  c.opt.ris_light_candidates};
      rays += pt::ris_direct_light(in, sampled ? &s : nullptr, u1, u2, nee_u1, nee_u2, rng.get1d(),
                                   T, L, &pending);
    }
    if (!sampled) return rays;
    after_ris = ris && !s.delta;
    const V3 wl = s.wo;
    for (int k = 0; k < n; ++k) T[k] *= s.weight[k];
    specular = s.delta;
    prev_pdf = s.pdf;
    d = sp.to_world(wl).normalized();
    if (d.dot(sp.ng) <= 0) return rays;  // below the geometric surface
    o = origin;
    // A path that ends here traces the pending direct light's shadow ray itself.
    auto end = [&] { return rays + pending.resolve_by_shadow_ray(c.geo, o, d, n, L); };
    // Russian roulette after three bounces.
    double tmax = 0;
    for (int k = 0; k < n; ++k) {
      if (!std::isfinite(T[k])) return end();
      tmax = std::max(tmax, std::abs(T[k]));
    }
    if (!(tmax > 0)) return end();
    if (depth >= 3) {
      const double q = std::min(1.0, tmax);
      if (rng.get1d() >= q) return end();
      for (int k = 0; k < n; ++k) T[k] /= q;
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

RenderImage render(const RenderScene& scene,
                   const std::vector<std::shared_ptr<const Svbrdf>>& materials,
                   const RenderLights& lights, const RenderOptions& opt) {
  if (opt.width <= 0 || opt.height <= 0 || opt.width > 16384 || opt.height > 16384)
    throw InputError("render: image size must be 1..16384 pixels a side");
  if (opt.spp <= 0) throw InputError("render: samples per pixel must be > 0");
  if (opt.half_images && opt.spp < 2)
    throw InputError("render: half images need at least 2 samples per pixel");
  if (opt.max_depth < 1) throw InputError("render: max depth must be >= 1");
  if (opt.wavelengths < 1 || opt.wavelengths > pt::kMaxWavelengths)
    throw InputError("render: wavelengths per path must be 1..16");
  if (opt.ris_brdf_candidates < 1 || opt.ris_brdf_candidates > pt::kMaxRisBrdfCandidates)
    throw InputError("render: RIS BRDF candidates must be 1..16");
  if (opt.ris_light_candidates < 1 || opt.ris_light_candidates > pt::kMaxRisLightCandidates)
    throw InputError("render: RIS light candidates must be 1..4");
  if (materials.empty()) throw InputError("render: no material");
  for (const auto& m : materials)
    if (!m) throw InputError("render: null material");
  const auto t0 = std::chrono::steady_clock::now();
  pt::PreviewGeometry geo(scene);
  // Uniform materials ignore the texture coordinates.
  geo.set_texture_coordinates(!std::all_of(materials.begin(), materials.end(), [](const auto& m) {
    return dynamic_cast<const UniformSvbrdf*>(m.get()) != nullptr;
  }));
  if (materials.size() != 1 && int(materials.size()) != geo.object_count())
    throw InputError("render: scene '" + preview_scene_name(scene.kind) + "' has " +
                     std::to_string(geo.object_count()) + " objects; give 1 or " +
                     std::to_string(geo.object_count()) + " materials, not " +
                     std::to_string(materials.size()));
  const pt::LightSet ls(lights);
  if (ls.count() == 0) throw InputError("render: no light (give an environment map or lights)");
  const auto& spec = pt::SpectralTables::get();
  std::vector<pt::SpectralMaterial> mats;
  for (const auto& m : materials) mats.emplace_back(m);
  const PathContext ctx{geo, ls, mats, opt, spec};
  const Eigen::Matrix3d to_rgb = xyz_to_linear_srgb_matrix();

  RenderImage img;
  img.width = opt.width;
  img.height = opt.height;
  img.rgb.assign(std::size_t(opt.width) * opt.height * 3, 0.0f);
  const pt::Camera& cam = geo.camera();
  const int n = opt.wavelengths;
  std::atomic<int> rows_done{0};
  std::uint64_t rays = 0;
  const int threads = resolve_thread_count(opt.threads);
  const auto kind = opt.sampler == RenderSampler::Sobol ? pt::PathSamplerKind::Sobol
                                                        : pt::PathSamplerKind::Independent;
  const bool halves = opt.half_images;
  if (halves) {
    img.half_rgb[0].assign(img.rgb.size(), 0.0f);
    img.half_rgb[1].assign(img.rgb.size(), 0.0f);
  }
  const int first_half = opt.spp / 2;  // samples [0, spp/2) and [spp/2, spp)
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads) reduction(+ : rays)
  for (int y = 0; y < opt.height; ++y) {
    for (int x = 0; x < opt.width; ++x) {
      const std::uint64_t pixel = std::uint64_t(y) * opt.width + x;
      Eigen::Vector3d xyz[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
      for (int s = 0; s < opt.spp; ++s) {
        pt::PathSampler rng(kind, opt.seed, pixel, std::uint32_t(s), std::uint32_t(opt.spp));
        double jx, jy;
        rng.get2d(jx, jy);
        double lambda[pt::kMaxWavelengths], L[pt::kMaxWavelengths];
        for (int k = 0; k < n; ++k) L[k] = 0;
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
        Eigen::Vector3d sx = Eigen::Vector3d::Zero();
        for (int k = 0; k < n; ++k)
          if (L[k] != 0) sx += (L[k] * lweight[k]) * spec.xyz_weight(lambda[k]);
        if (sx.allFinite()) xyz[s < first_half ? 0 : 1] += sx / n;
      }
      const Eigen::Vector3d rgb = to_rgb * ((xyz[0] + xyz[1]) / opt.spp);
      for (int ch = 0; ch < 3; ++ch) img.rgb[pixel * 3 + ch] = float(rgb[ch]);
      if (halves)
        for (int h = 0; h < 2; ++h) {
          const int count = h == 0 ? first_half : opt.spp - first_half;
          const Eigen::Vector3d hr = to_rgb * (xyz[h] / count);
          for (int ch = 0; ch < 3; ++ch) img.half_rgb[h][pixel * 3 + ch] = float(hr[ch]);
        }
    }
    const int done = ++rows_done;
    if (opt.progress && omp_get_thread_num() == 0) opt.progress(double(done) / opt.height);
  }
  if (opt.progress) opt.progress(1.0);
  img.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  img.samples_per_second = double(opt.width) * opt.height * opt.spp / std::max(img.seconds, 1e-9);
  img.rays = rays;
  std::ostringstream os;
  os << "scene " << preview_scene_name(scene.kind) << "; materials:";
  for (const auto& m : materials) os << " [" << m->describe() << "]";
  os << "; lights:";
  if (lights.uniform_white_env) os << " uniform white environment";
  if (!lights.envmap_path.empty())
    os << " envmap " << lights.envmap_path << " x" << lights.envmap_scale;
  os << " points " << lights.points.size() << " spheres " << lights.spheres.size() << " disks "
     << lights.disks.size() << "; " << opt.width << "x" << opt.height << ", " << opt.spp << " spp, "
     << n << " wavelengths/path, max depth " << opt.max_depth << ", seed " << opt.seed << ", mis "
     << (opt.mis == MisMode::Mis        ? "power"
         : opt.mis == MisMode::BrdfOnly ? "brdf_only"
                                        : "light_only")
     << ", sampler " << render_sampler_name(opt.sampler) << ", direct light "
     << direct_light_name(opt.direct);
  if (opt.direct == DirectLight::Ris)
    os << " (" << opt.ris_brdf_candidates << " BRDF + " << opt.ris_light_candidates
       << " light candidates)";
  img.settings = os.str();
  return img;
}

}  // namespace microbrdf
