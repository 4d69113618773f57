// The preview renderer: the Dong Fig. 10 cylinder pair under an environment map, in samples
// (camera paths) per second, against a bare Embree primary-ray loop over the same geometry
// (one closest-hit query per sample, nothing else) in the same run. 512 x 512 at 4 spp here;
// the full 512 x 512 x 64 figure is measured with the CLI (docs/benchmarks.md).
#include <benchmark/benchmark.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <memory>
#include <random>

#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/render.hpp"
#include "microbrdf/tabulated_distribution.hpp"
#include "render/distribution2d.hpp"
#include "render/envmap.hpp"
#include "render/path_sampler.hpp"
#include "render/scene.hpp"

using namespace microbrdf;

namespace {

constexpr int kSize = 512, kSpp = 4, kThreads = 2;

/// Process CPU time of all threads, seconds: on the shared machine wall-clock rates depend on
/// the other jobs; per-CPU-second rates much less.
double cpu_seconds() { return double(std::clock()) / CLOCKS_PER_SEC; }

std::shared_ptr<const Svbrdf> material(bool tabulated) {
  auto f = std::make_shared<ConductorFresnel>(metal("SS-austenitic"));
  std::shared_ptr<const MicrofacetDistribution> d;
  BeckmannDistribution b(0.007, 0.14);
  // Dong Fig. 12 stainless #4 Beckmann fit; "tabulated" is that NDF as a 1025^2 table (the form
  // measured NDFs take), sampled by NdfSampler and shadowed by the sigma+ grid.
  if (tabulated)
    d = std::make_shared<TabulatedDistribution>(tabulate(b, "beckmann"));
  else
    d = std::make_shared<BeckmannDistribution>(b);
  return std::make_shared<UniformSvbrdf>(std::make_shared<MicrofacetBrdf>(d, f));
}

RenderLights courtyard() {
  RenderLights l;
  l.envmap_path = std::string(MICROBRDF_DATA) + "/envmaps/blender_courtyard.exr";
  return l;
}

void BM_RenderCylinders(benchmark::State& state) {
  RenderScene sc;
  sc.kind = PreviewScene::Cylinders;
  const auto mats = std::vector<std::shared_ptr<const Svbrdf>>{material(state.range(0) != 0)};
  const auto lights = courtyard();
  RenderOptions o;
  o.width = o.height = kSize;
  o.spp = kSpp;
  o.threads = kThreads;
  std::uint64_t rays = 0;
  const double c0 = cpu_seconds();
  for (auto _ : state) {
    auto img = render(sc, mats, lights, o);
    rays += img.rays;
    benchmark::DoNotOptimize(img.rgb.data());
  }
  const double cpu = cpu_seconds() - c0;
  const double samples = double(kSize) * kSize * kSpp;
  state.counters["samples/s"] =
      benchmark::Counter(samples, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["rays/s"] = benchmark::Counter(double(rays), benchmark::Counter::kIsRate);
  state.counters["samples/cpu-s"] = samples * double(state.iterations()) / cpu;
  state.SetLabel(std::string(state.range(0) ? "tabulated 1025^2" : "analytic") +
                 " Beckmann 0.007/0.14, SS, courtyard.exr, 512x512x4, 2 threads (includes scene "
                 "build and env-map load)");
}
BENCHMARK(BM_RenderCylinders)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

// The comparison strip's materials: a 1025^2 tabulated Beckmann (0.007, 0.14) and ellipsoid,
// Beckmann and GGX fits of it, stainless steel.
std::vector<std::vector<std::shared_ptr<const Svbrdf>>> strip_variants() {
  auto f = std::make_shared<ConductorFresnel>(metal("SS-austenitic"));
  auto uniform = [&](std::shared_ptr<const MicrofacetDistribution> d) {
    return std::vector<std::shared_ptr<const Svbrdf>>{
        std::make_shared<UniformSvbrdf>(std::make_shared<MicrofacetBrdf>(std::move(d), f))};
  };
  return {{material(true)},
          uniform(std::make_shared<EllipsoidDistribution>(EllipsoidParams{0.006, 0.13})),
          uniform(std::make_shared<BeckmannDistribution>(0.0075, 0.15)),
          uniform(std::make_shared<GgxDistribution>(0.006, 0.12))};
}

// The comparison strip of `predict`: a measured (tabulated) NDF and three analytic fits of it on
// the cylinder pair. Arg 0: four separate renders (the yardstick, same run); arg 1: one
// render_variants pass with the weights predict uses (the tabulated NDF half of the draws).
// Both produce the same four images in expectation; the counter is CPU seconds per set of four.
void BM_RenderStrip(benchmark::State& state) {
  RenderScene sc;
  sc.kind = PreviewScene::Cylinders;
  const auto variants = strip_variants();
  const auto lights = courtyard();
  RenderOptions o;
  o.width = o.height = 256;
  o.spp = kSpp;
  o.threads = kThreads;
  o.direct = DirectLight::Mis;  // shared paths use MIS: the separate renders alike
  const bool shared = state.range(0) != 0;
  if (shared) o.variant_weights = {3, 1, 1, 1};
  const double c0 = cpu_seconds();
  for (auto _ : state) {
    if (shared) {
      benchmark::DoNotOptimize(render_variants(sc, variants, lights, o).back().rgb.data());
    } else {
      for (const auto& v : variants) benchmark::DoNotOptimize(render(sc, v, lights, o).rgb.data());
    }
  }
  state.counters["cpu_s_per_set"] = (cpu_seconds() - c0) / double(state.iterations());
  state.SetLabel(std::string(shared ? "one shared-path pass" : "four separate renders") +
                 ": tabulated Beckmann 0.007/0.14 + ellipsoid, Beckmann, GGX fits, SS, "
                 "courtyard, 256x256x4, 2 threads");
}
BENCHMARK(BM_RenderStrip)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

// predict's studio view: the strip's pass under the courtyard (the four variants of
// BM_RenderStrip) and the measured NDF under the studio map at half the size with 4x the
// samples. Arg 0: the pass and a separate studio render (the yardstick, same run); arg 1: one
// render_light_sets pass with the studio as a second light set at the full size (predict then
// averages 2 x 2 pixels: an unbiased estimate of the same image). CPU seconds per set.
void BM_RenderStudioSet(benchmark::State& state) {
  RenderScene sc;
  sc.kind = PreviewScene::Cylinders;
  const auto variants = strip_variants();
  RenderLights studio;
  studio.envmap_path = std::string(MICROBRDF_DATA) + "/envmaps/blender_studio.exr";
  RenderOptions o;
  o.width = o.height = 256;
  o.spp = kSpp;
  o.threads = kThreads;
  o.direct = DirectLight::Mis;
  o.wavelengths = 4;  // as predict
  o.variant_weights = {3, 1, 1, 1};
  RenderOptions half = o;
  half.width = half.height = 128;
  half.spp = 4 * kSpp;
  half.variant_weights.clear();
  const bool shared = state.range(0) != 0;
  const double c0 = cpu_seconds();
  for (auto _ : state) {
    if (shared) {
      benchmark::DoNotOptimize(
          render_light_sets(sc, variants, {courtyard(), studio}, o).back().rgb.data());
    } else {
      benchmark::DoNotOptimize(render_variants(sc, variants, courtyard(), o).back().rgb.data());
      benchmark::DoNotOptimize(render(sc, variants.front(), studio, half).rgb.data());
    }
  }
  state.counters["cpu_s_per_set"] = (cpu_seconds() - c0) / double(state.iterations());
  state.SetLabel(std::string(shared ? "one pass, two light sets" : "strip pass + studio render") +
                 ": tabulated Beckmann 0.007/0.14 + three fits, SS, courtyard and studio, "
                 "256x256x4 (studio 128x128x16), 2 threads");
}
BENCHMARK(BM_RenderStudioSet)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

// The reference: the same camera rays (jittered, same count), closest hit only.
void BM_EmbreePrimaryRays(benchmark::State& state) {
  RenderScene sc;
  sc.kind = PreviewScene::Cylinders;
  const pt::PreviewGeometry geo(sc);
  const pt::Camera& cam = geo.camera();
  double hits = 0;
  const double c0 = cpu_seconds();
  for (auto _ : state) {
    double sum = 0;
#pragma omp parallel for schedule(dynamic, 1) num_threads(kThreads) reduction(+ : sum)
    for (int y = 0; y < kSize; ++y) {
      std::minstd_rand rng(y);
      std::uniform_real_distribution<double> u(0, 1);
      for (int x = 0; x < kSize; ++x)
        for (int s = 0; s < kSpp; ++s)
          sum +=
              geo.intersect_bare(cam.position, cam.direction(x + u(rng), y + u(rng), kSize, kSize));
    }
    hits += sum;
    benchmark::DoNotOptimize(sum);
  }
  const double cpu = cpu_seconds() - c0;
  state.counters["rays/s"] = benchmark::Counter(double(kSize) * kSize * kSpp,
                                                benchmark::Counter::kIsIterationInvariantRate);
  state.counters["rays/cpu-s"] = double(kSize) * kSize * kSpp * double(state.iterations()) / cpu;
  // Mean hit distance (misses count -1): the same rays give the same number in every run.
  state.counters["mean_t"] = hits / (double(kSize) * kSize * kSpp * double(state.iterations()));
  state.SetLabel("cylinder pair, 512x512x4 camera rays, 2 threads");
}
BENCHMARK(BM_EmbreePrimaryRays)->Unit(benchmark::kMillisecond)->UseRealTime();

// Environment-map light samples: the renderer's draw (guide tables and one record per pixel,
// render/distribution2d.hpp) against the plain inversion it replaced, in the same run: binary
// searches (std::upper_bound) of the row CDF and the chosen row's CDF, then the density and the
// radiance from their own arrays. The courtyard map (1024 x 512), 2^20 draws of random points
// per iteration, one thread; the draws land on the same cells.
struct EnvTables {
  pt::RgbFloatImage img;
  std::vector<double> row_cdf, col_cdf;
  std::vector<float> density;
  std::unique_ptr<pt::PiecewiseConstant2D> dist;
  std::vector<double> us;
};

const EnvTables& env_tables() {
  static const EnvTables t = [] {
    EnvTables e;
    e.img = pt::read_envmap_image(std::string(MICROBRDF_DATA) + "/envmaps/blender_courtyard.exr");
    const std::size_t w = e.img.width, h = e.img.height;
    std::vector<double> f(w * h);
    double sum = 0;
    for (std::size_t r = 0; r < h; ++r)
      for (std::size_t c = 0; c < w; ++c) {
        const float* p = &e.img.rgb[(r * w + c) * 3];
        f[r * w + c] =
            std::max({p[0], p[1], p[2]}) * std::sin(M_PI * (double(r) + 0.5) / double(h));
        sum += f[r * w + c];
      }
    e.dist = std::make_unique<pt::PiecewiseConstant2D>(f, w, h, e.img.rgb.data());
    e.row_cdf.assign(h + 1, 0.0);
    e.col_cdf.assign((w + 1) * h, 0.0);
    e.density.resize(w * h);
    for (std::size_t r = 0; r < h; ++r) {
      double* c = &e.col_cdf[r * (w + 1)];
      for (std::size_t k = 0; k < w; ++k) {
        c[k + 1] = c[k] + f[r * w + k];
        e.density[r * w + k] = float(f[r * w + k] * double(w * h) / sum);
      }
      e.row_cdf[r + 1] = e.row_cdf[r] + c[w];
    }
    std::mt19937_64 g(7);
    std::uniform_real_distribution<double> u(0, 1);
    e.us.resize(2 << 20);
    for (auto& x : e.us) x = u(g);
    return e;
  }();
  return t;
}

void BM_EnvmapDraw(benchmark::State& state) {
  const EnvTables& e = env_tables();
  const std::size_t n = e.us.size() / 2;
  for (auto _ : state) {
    double acc = 0;
    for (std::size_t i = 0; i < n; ++i) {
      double u, v, pdf;
      const std::size_t cell = e.dist->sample(e.us[2 * i], e.us[2 * i + 1], u, v, pdf);
      acc += pdf + e.dist->payload(cell)[1] + u + v;
    }
    benchmark::DoNotOptimize(acc);
  }
  state.counters["draws/s"] =
      benchmark::Counter(double(n), benchmark::Counter::kIsIterationInvariantRate);
  state.SetLabel("guide tables, one record per pixel");
}
BENCHMARK(BM_EnvmapDraw)->Unit(benchmark::kMillisecond);

void BM_EnvmapDrawBinarySearch(benchmark::State& state) {
  const EnvTables& e = env_tables();
  const std::size_t n = e.us.size() / 2, w = e.img.width, h = e.img.height;
  auto invert = [](const double* c, std::size_t m, double x, double& frac) {
    const double t = x * c[m];
    std::size_t k = std::size_t(std::upper_bound(c, c + m + 1, t) - c);
    k = std::clamp<std::size_t>(k, 1, m) - 1;
    const double width = c[k + 1] - c[k];
    frac = width > 0 ? (t - c[k]) / width : 0.5;
    return k;
  };
  for (auto _ : state) {
    double acc = 0;
    for (std::size_t i = 0; i < n; ++i) {
      double fu, fv;
      const std::size_t r = invert(e.row_cdf.data(), h, e.us[2 * i + 1], fv);
      const std::size_t c = invert(&e.col_cdf[r * (w + 1)], w, e.us[2 * i], fu);
      acc += e.density[r * w + c] + e.img.rgb[(r * w + c) * 3 + 1] + (double(c) + fu) / double(w) +
             (double(r) + fv) / double(h);
    }
    benchmark::DoNotOptimize(acc);
  }
  state.counters["draws/s"] =
      benchmark::Counter(double(n), benchmark::Counter::kIsIterationInvariantRate);
  state.SetLabel("reference: binary searches, separate density and radiance arrays");
}
BENCHMARK(BM_EnvmapDrawBinarySearch)->Unit(benchmark::kMillisecond);

// The renderer's random numbers: 2D requests of 32-sample pixels (8 per path, one thread), each
// sampler hashing its own requests (arg 0: how every path drew before, the yardstick) or the
// pixel's hashes shared by its samples (arg 1: PixelHashes, what render does). The same numbers
// either way (tests/test_path_sampler.cpp); the counter is nanoseconds per 2D request.
void BM_PathSampler2d(benchmark::State& state) {
  const bool shared = state.range(0) != 0;
  constexpr int kPixels = 1 << 14, kRequests = 8, kPerPixel = 32;
  double sum = 0;
  const double c0 = cpu_seconds();
  for (auto _ : state) {
    for (int p = 0; p < kPixels; ++p) {
      pt::PixelHashes hashes(1, std::uint64_t(p));
      for (std::uint32_t s = 0; s < kPerPixel; ++s) {
        pt::PathSampler r =
            shared ? pt::PathSampler(pt::PathSamplerKind::Sobol, hashes, s, kPerPixel)
                   : pt::PathSampler(pt::PathSamplerKind::Sobol, 1, std::uint64_t(p), s, kPerPixel);
        for (int k = 0; k < kRequests; ++k) {
          double u1, u2;
          r.get2d(u1, u2);
          sum += u1 + u2;
        }
      }
    }
  }
  benchmark::DoNotOptimize(sum);
  state.counters["ns_per_request"] =
      (cpu_seconds() - c0) * 1e9 / (double(state.iterations()) * kPixels * kPerPixel * kRequests);
  state.counters["checksum"] = sum / double(state.iterations());
  state.SetLabel(shared ? "pixel hashes shared by its samples" : "each sample hashes its own");
}
BENCHMARK(BM_PathSampler2d)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
