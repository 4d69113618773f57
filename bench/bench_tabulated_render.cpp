// The path tracer's per-vertex work on the material of `microbrdf predict`'s demo: the measured
// (filtered, 513^2) NDF of tests/data/sample-land.x3p (levelled poly3, filter sigma 5 um) as a
// MicrofacetBrdf with copper's Fresnel term, through SpectralMaterial as render.cpp calls it.
// Per vertex: view(wv), eval(wl) with the MIS density (a light sample), sample() (the BRDF
// sample), with four hero wavelengths. The yardstick in the same run: the same calls on an
// analytic GGX of the table's rms slope (its sampler and density are closed forms, and it
// touches no large table). Counters: ns per vertex; the table ratio is the figure to compare
// between builds (docs/benchmarks.md, "Tabulated NDF in the renderer").
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "bench_load.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/io.hpp"
#include "microbrdf/level.hpp"
#include "microbrdf/microfacet.hpp"
#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/ndf_estimate.hpp"
#include "microbrdf/svbrdf.hpp"
#include "microbrdf/tabulated_distribution.hpp"
#include "render/material.hpp"

using namespace microbrdf;

namespace {

const TabulatedNdf& demo_table() {
  static const TabulatedNdf t = [] {
    Surface s = read_surface(std::string(MICROBRDF_TEST_DATA) + "/sample-land.x3p");
    level_surface(s, LevelingSpec::parse("poly3"));
    NdfEstimateOptions o;
    o.method = NdfMethod::Filtered;
    o.resolution = 513;
    o.filter_sigma_m = 5e-6;
    return estimate_ndf(s, o);
  }();
  return t;
}

std::shared_ptr<const Svbrdf> material(bool tabulated) {
  std::shared_ptr<const MicrofacetDistribution> d;
  if (tabulated) {
    d = std::make_shared<TabulatedDistribution>(demo_table());
  } else {
    const Eigen::Matrix2d c = demo_table().slope_covariance();
    d = std::make_shared<GgxDistribution>(std::sqrt(c(0, 0) + c(1, 1)));  // alpha^2 = 2 sigma^2
  }
  const auto f = std::make_shared<ConductorFresnel>(metal("Cu"));
  return std::make_shared<UniformSvbrdf>(std::make_shared<MicrofacetBrdf>(d, f));
}

struct Vertex {
  Vec3 wv, wl;
  double u1, u2;
};

// Viewer directions cosine-distributed, light directions uniform over the hemisphere (an
// environment map's samples are spread over it), independent sample numbers.
std::vector<Vertex> vertices(std::size_t n) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vertex> out(n);
  for (auto& x : out) {
    const double r = std::sqrt(u(rng)), p = 2 * M_PI * u(rng);
    x.wv = Vec3(r * std::cos(p), r * std::sin(p), std::sqrt(std::max(0.0, 1 - r * r)));
    const double z = u(rng), q = 2 * M_PI * u(rng), s = std::sqrt(1 - z * z);
    x.wl = Vec3(s * std::cos(q), s * std::sin(q), z);
    x.u1 = u(rng);
    x.u2 = u(rng);
  }
  return out;
}

// state.range(0): 1 = the measured table, 0 = GGX (the yardstick).
void BM_TabulatedRenderVertex(benchmark::State& state) {
  const bool tab = state.range(0) != 0;
  static const auto mt = material(true), mg = material(false);
  const pt::SpectralMaterial m(tab ? mt : mg);
  if (!m.fast()) state.SkipWithError("material not on the fast path");
  const double lambda[4] = {450e-9, 530e-9, 610e-9, 690e-9};
  pt::SpectralMaterial::Wavelengths w;
  m.prepare(lambda, 4, w);
  const auto vs = vertices(1 << 14);
  double sum = 0, count = 0, reflected = 0;
  for (auto _ : state) {
    for (const Vertex& x : vs) {
      const auto vw = m.view(x.wv);
      double f[4], pdf = 0;
      if (m.eval(0, 0, vw, x.wl, w, f, &pdf)) {
        sum += f[0] + pdf;
        reflected += 1;
      }
      pt::SpectralMaterial::Sample s;
      if (m.sample(0, 0, vw, x.u1, x.u2, w, s)) sum += s.weight[0] + s.pdf;
    }
    count += static_cast<double>(vs.size());
  }
  state.counters["ns_per_vertex"] =
      benchmark::Counter(count, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["light_f_nonzero"] = reflected / count;
  // The mean of the numbers summed (the same in every build that gives the same results).
  state.counters["checksum"] = sum / count;
  state.counters["load"] = bench::load_average();
}
BENCHMARK(BM_TabulatedRenderVertex)
    ->Arg(0)
    ->Arg(1)
    ->ArgName("tabulated")
    ->Unit(benchmark::kMillisecond)
    ->MinTime(2.0);

}  // namespace
