// Reflectance models: evaluations/s and samples/s for each NDF and for the full microfacet BRDF,
// with peer references in the same run: Fresnel complex form vs the real Siegel form, analytic
// Smith G1 vs G1 by projected-area quadrature (brute force), and the visible-normal sampler vs
// drawing plain D(m)(m.n) samples.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "microbrdf/fresnel.hpp"
#include "microbrdf/microfacet.hpp"
#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/quadrature.hpp"
#include "microbrdf/tabulated_distribution.hpp"

using namespace microbrdf;

namespace {

constexpr std::size_t kBatch = 4096;

std::vector<Vec3> directions(unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3> v(kBatch);
  for (auto& d : v) {
    double ct = u(rng), st = std::sqrt(1 - ct * ct), p = 6.283185307179586 * u(rng);
    d = Vec3(st * std::cos(p), st * std::sin(p), ct);
  }
  return v;
}

std::shared_ptr<MicrofacetDistribution> ndf(int which) {
  switch (which) {
    case 0:
      return make_distribution(NdfSpec{"beckmann", 0.2, 0.4, 0.3, 0, 0, 0, {}});
    case 1:
      return make_distribution(NdfSpec{"ggx", 0.2, 0.4, 0.3, 0, 0, 0, {}});
    case 2:
      return make_distribution(NdfSpec{"ellipsoid", 0.2, 0.4, 0, 0.1, -0.05, 0.3, {}});
    default: {  // the Beckmann lobe above tabulated on 1025^2 (built once: ~1.5 s)
      static const auto t = std::make_shared<TabulatedDistribution>(tabulate(
          *make_distribution(NdfSpec{"beckmann", 0.2, 0.4, 0.3, 0, 0, 0, {}}), "beckmann", 1025));
      return t;
    }
  }
}
const char* kNames[] = {"beckmann", "ggx", "ellipsoid", "tabulated beckmann 1025^2"};

void rate(benchmark::State& state, const char* name) {
  state.counters[name] = benchmark::Counter(static_cast<double>(kBatch),
                                            benchmark::Counter::kIsIterationInvariantRate);
}

void BM_NdfEval(benchmark::State& state) {
  auto d = ndf(static_cast<int>(state.range(0)));
  auto m = directions(1);
  for (auto _ : state) {
    double s = 0;
    for (const auto& x : m) s += d->D(x);
    benchmark::DoNotOptimize(s);
  }
  state.SetLabel(kNames[state.range(0)]);
  rate(state, "evals/s");
}

void BM_NdfG1Analytic(benchmark::State& state) {
  auto d = ndf(static_cast<int>(state.range(0)));
  auto v = directions(2);
  for (auto _ : state) {
    double s = 0;
    for (const auto& x : v) s += d->G1(x);
    benchmark::DoNotOptimize(s);
  }
  state.SetLabel(kNames[state.range(0)]);
  rate(state, "evals/s");
}

// Brute-force peer: G1 = (v.n) / integral D <v.m>+ dw on a 128 x 256 product grid.
void BM_NdfG1Quadrature(benchmark::State& state) {
  auto d = ndf(static_cast<int>(state.range(0)));
  std::vector<double> x, w;
  gauss_legendre(128, x, w);
  Vec3 v(std::sin(1.0), 0, std::cos(1.0));
  for (auto _ : state) {
    double s = 0;
    for (int i = 0; i < 128; ++i) {
      double mu = 0.5 * (x[i] + 1), st = std::sqrt(1 - mu * mu);
      for (int j = 0; j < 256; ++j) {
        double p = 6.283185307179586 * (j + 0.5) / 256;
        Vec3 m(st * std::cos(p), st * std::sin(p), mu);
        s += 0.5 * w[i] * d->D(m) * std::max(0.0, v.dot(m)) * 6.283185307179586 / 256;
      }
    }
    benchmark::DoNotOptimize(v.z() / s);
  }
  state.SetLabel(kNames[state.range(0)]);
  state.counters["evals/s"] = benchmark::Counter(1, benchmark::Counter::kIsIterationInvariantRate);
}

void BM_NdfSampleVisible(benchmark::State& state) {
  auto d = ndf(static_cast<int>(state.range(0)));
  auto v = directions(3);
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> us(2 * kBatch);
  for (auto& x : us) x = u(rng);
  for (auto _ : state) {
    Vec3 s = Vec3::Zero();
    for (std::size_t k = 0; k < kBatch; ++k) s += d->sample_visible(v[k], us[2 * k], us[2 * k + 1]);
    benchmark::DoNotOptimize(s);
  }
  state.SetLabel(kNames[state.range(0)]);
  rate(state, "samples/s");
}

void BM_NdfPdfVisible(benchmark::State& state) {
  auto d = ndf(static_cast<int>(state.range(0)));
  auto v = directions(5), m = directions(6);
  for (auto _ : state) {
    double s = 0;
    for (std::size_t k = 0; k < kBatch; ++k) s += d->pdf_visible(v[k], m[k]);
    benchmark::DoNotOptimize(s);
  }
  state.SetLabel(kNames[state.range(0)]);
  rate(state, "evals/s");
}

void BM_BrdfEval(benchmark::State& state) {
  MicrofacetBrdf b(ndf(static_cast<int>(state.range(0))),
                   std::make_shared<ConductorFresnel>(metal("Cu")));
  auto wi = directions(7), wo = directions(8);
  for (auto _ : state) {
    double s = 0;
    for (std::size_t k = 0; k < kBatch; ++k) s += b.eval(wi[k], wo[k], 555e-9);
    benchmark::DoNotOptimize(s);
  }
  state.SetLabel(kNames[state.range(0)]);
  rate(state, "evals/s");
}

void BM_BrdfSample(benchmark::State& state) {
  MicrofacetBrdf b(ndf(static_cast<int>(state.range(0))),
                   std::make_shared<ConductorFresnel>(metal("Cu")));
  auto wi = directions(9);
  std::mt19937_64 rng(10);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> us(2 * kBatch);
  for (auto& x : us) x = u(rng);
  for (auto _ : state) {
    double s = 0;
    for (std::size_t k = 0; k < kBatch; ++k)
      if (auto r = b.sample(wi[k], us[2 * k], us[2 * k + 1], 555e-9)) s += r->weight;
    benchmark::DoNotOptimize(s);
  }
  state.SetLabel(kNames[state.range(0)]);
  rate(state, "samples/s");
}

void BM_FresnelComplex(benchmark::State& state) {
  std::vector<double> c(kBatch);
  for (std::size_t k = 0; k < kBatch; ++k) c[k] = (k + 0.5) / kBatch;
  for (auto _ : state) {
    double s = 0;
    for (double x : c) s += fresnel_conductor(x, {1.02, 2.577});
    benchmark::DoNotOptimize(s);
  }
  rate(state, "evals/s");
}

void BM_FresnelSiegel(benchmark::State& state) {
  std::vector<double> c(kBatch);
  for (std::size_t k = 0; k < kBatch; ++k) c[k] = (k + 0.5) / kBatch;
  for (auto _ : state) {
    double s = 0;
    for (double x : c) s += fresnel_conductor_siegel(x, 1.02, 2.577);
    benchmark::DoNotOptimize(s);
  }
  rate(state, "evals/s");
}

void BM_MetalColour(benchmark::State& state) {
  auto au = metal("Au");
  for (auto _ : state)
    benchmark::DoNotOptimize(
        xyz_to_linear_srgb(reflectance_to_xyz(au.normal_reflectance_spectrum())));
}

}  // namespace

BENCHMARK(BM_NdfEval)->DenseRange(0, 3);
BENCHMARK(BM_NdfG1Analytic)->DenseRange(0, 3);
BENCHMARK(BM_NdfG1Quadrature)->DenseRange(0, 2);
BENCHMARK(BM_NdfSampleVisible)->DenseRange(0, 3);
BENCHMARK(BM_NdfPdfVisible)->DenseRange(0, 3);
BENCHMARK(BM_BrdfEval)->DenseRange(0, 3);
BENCHMARK(BM_BrdfSample)->DenseRange(0, 3);
BENCHMARK(BM_FresnelComplex);
BENCHMARK(BM_FresnelSiegel);
BENCHMARK(BM_MetalColour);
