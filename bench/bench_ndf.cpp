// Tabulated NDFs: bilinear eval(), importance sampling (NdfSampler: two binary searches + exact
// bilinear inversion) next to a brute-force reference in the same run (linear search over the
// flat CDF of all cell masses, piecewise-constant within the cell), and the instrument
// convolution at the default resolution (N = 1025, FWHM 1.5 deg, Dong 2015 section 7).
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "microbrdf/microfacet.hpp"
#include "microbrdf/ndf_convolve.hpp"
#include "microbrdf/ndf_sampler.hpp"
#include "microbrdf/tabulated_distribution.hpp"

using namespace microbrdf;

namespace {

// The library's Beckmann table (tabulate in microfacet.hpp).
TabulatedNdf beckmann(std::size_t n, double alpha) {
  NdfSpec spec;
  spec.model = "beckmann";
  spec.alpha_x = spec.alpha_y = alpha;
  TabulatedNdf t = tabulate(*make_distribution(spec), "beckmann", n);
  return t;
}

std::vector<double> uniforms(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> v(n);
  for (double& x : v) x = u(rng);
  return v;
}

void BM_NdfEval(benchmark::State& state) {
  const TabulatedNdf t = beckmann(1025, 0.3);
  auto u = uniforms(2 * 4096, 1);
  std::vector<Eigen::Vector3d> dirs;
  for (std::size_t i = 0; i < 4096; ++i) {
    const double ph = 2 * std::numbers::pi * u[2 * i], ct = u[2 * i + 1];
    const double st = std::sqrt(1 - ct * ct);
    dirs.emplace_back(st * std::cos(ph), st * std::sin(ph), ct);
  }
  for (auto _ : state) {
    double acc = 0;
    for (const auto& m : dirs) acc += t.eval(m);
    benchmark::DoNotOptimize(acc);
  }
  state.counters["evals/s"] = benchmark::Counter(static_cast<double>(dirs.size()),
                                                 benchmark::Counter::kIsIterationInvariantRate);
}

void BM_NdfSamplerBuild(benchmark::State& state) {
  const TabulatedNdf t = beckmann(static_cast<std::size_t>(state.range(0)), 0.3);
  for (auto _ : state) {
    NdfSampler s(t);
    benchmark::DoNotOptimize(s.normalisation());
  }
}

void BM_NdfSample(benchmark::State& state) {
  const TabulatedNdf t = beckmann(static_cast<std::size_t>(state.range(0)), 0.3);
  const NdfSampler s(t);
  const auto u = uniforms(2 * 4096, 2);
  for (auto _ : state) {
    Eigen::Vector3d acc = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < 4096; ++i) acc += s.sample(u[2 * i], u[2 * i + 1]);
    benchmark::DoNotOptimize(acc);
  }
  state.counters["samples/s"] =
      benchmark::Counter(4096, benchmark::Counter::kIsIterationInvariantRate);
}

// Brute force reference: one flat CDF over all (N-1)^2 cells, linear search, uniform jitter in
// the cell (piecewise constant, so not even the same density), rejection outside the disk.
void BM_NdfSampleBruteForce(benchmark::State& state) {
  const TabulatedNdf t = beckmann(static_cast<std::size_t>(state.range(0)), 0.3);
  const std::size_t c = t.resolution() - 1;
  std::vector<double> cdf(c * c);
  double sum = 0;
  for (std::size_t cy = 0; cy < c; ++cy)
    for (std::size_t cx = 0; cx < c; ++cx) {
      sum += t.at(cx, cy) + t.at(cx + 1, cy) + t.at(cx, cy + 1) + t.at(cx + 1, cy + 1);
      cdf[cy * c + cx] = sum;
    }
  for (double& v : cdf) v /= sum;
  const auto u = uniforms(3 * 256, 3);
  const double h = t.spacing();
  for (auto _ : state) {
    Eigen::Vector3d acc = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < 256; ++i) {
      std::size_t k = 0;
      while (k + 1 < cdf.size() && cdf[k] <= u[3 * i]) ++k;
      const double x = t.node_x(k % c) + u[3 * i + 1] * h, y = t.node_y(k / c) + u[3 * i + 2] * h;
      acc += Eigen::Vector3d(x, y, std::sqrt(std::max(0.0, 1 - x * x - y * y)));
    }
    benchmark::DoNotOptimize(acc);
  }
  state.counters["samples/s"] =
      benchmark::Counter(256, benchmark::Counter::kIsIterationInvariantRate);
}

void BM_NdfConvolve1025Fwhm1p5deg(benchmark::State& state) {
  // alpha = 0.3: non-zero almost everywhere on the disk, so no rows are skipped (worst case).
  const TabulatedNdf t = beckmann(1025, 0.3);
  for (auto _ : state)
    benchmark::DoNotOptimize(convolve_angular_gaussian(t, 1.5 * std::numbers::pi / 180));
}

// What a path tracer asks of a tabulated distribution per shading point (a new view each
// time): G1 of the view, a light sample's D, G1 and sampling density, and a visible-normal
// sample with its density and G1 of the reflected direction. Beckmann alpha 0.3 at 1025^2
// (arg 1025) or 513^2 (arg 513), visible-normal tables at their defaults.
void BM_TabulatedShadingPoint(benchmark::State& state) {
  const TabulatedDistribution d(beckmann(static_cast<std::size_t>(state.range(0)), 0.3));
  constexpr std::size_t kPoints = 4096;
  auto u = uniforms(6 * kPoints, 3);
  std::vector<Eigen::Vector3d> views, lights;
  for (std::size_t i = 0; i < kPoints; ++i) {
    for (auto* out : {&views, &lights}) {
      const double* r = &u[6 * i + (out == &views ? 0 : 2)];
      const double ph = 2 * std::numbers::pi * r[0], ct = 0.02 + 0.98 * r[1];
      const double st = std::sqrt(1 - ct * ct);
      out->emplace_back(st * std::cos(ph), st * std::sin(ph), ct);
    }
  }
  for (auto _ : state) {
    double acc = 0;
    for (std::size_t i = 0; i < kPoints; ++i) {
      const Eigen::Vector3d& v = views[i];
      const Eigen::Vector3d& l = lights[i];
      acc += d.lambda(v);
      const Eigen::Vector3d h = (v + l).normalized();
      if (const double dh = d.D(h); dh > 0) acc += dh * d.lambda(l) + d.sampling_pdf(v, h);
      const Eigen::Vector3d m = d.sample_visible(v, u[6 * i + 4], u[6 * i + 5]);
      acc += d.sampling_pdf(v, m);
      const Eigen::Vector3d r = 2 * v.dot(m) * m - v;
      if (r.z() > 0) acc += d.lambda(r);
    }
    benchmark::DoNotOptimize(acc);
  }
  state.counters["points/s"] = benchmark::Counter(static_cast<double>(kPoints),
                                                  benchmark::Counter::kIsIterationInvariantRate);
  state.counters["sampling_MB"] = static_cast<double>(d.sampling_memory_bytes()) / 1e6;
}

}  // namespace

BENCHMARK(BM_TabulatedShadingPoint)->Arg(513)->Arg(1025);
BENCHMARK(BM_NdfEval);
BENCHMARK(BM_NdfSamplerBuild)->Arg(257)->Arg(1025)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NdfSample)->Arg(257)->Arg(1025);
BENCHMARK(BM_NdfSampleBruteForce)->Arg(257)->Arg(1025)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NdfConvolve1025Fwhm1p5deg)->Unit(benchmark::kMillisecond)->Iterations(2);
