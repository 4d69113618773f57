// The preview renderer: the Dong Fig. 10 cylinder pair under an environment map, in samples
// (camera paths) per second, against a bare Embree primary-ray loop over the same geometry
// (one closest-hit query per sample, nothing else) in the same run. 512 x 512 at 4 spp here;
// the full 512 x 512 x 64 figure is measured with the CLI (docs/benchmarks.md).
#include <benchmark/benchmark.h>
#include <omp.h>

#include <ctime>
#include <memory>
#include <random>

#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/render.hpp"
#include "microbrdf/tabulated_distribution.hpp"
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
  state.SetLabel("cylinder pair, 512x512x4 camera rays, 2 threads");
}
BENCHMARK(BM_EmbreePrimaryRays)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
