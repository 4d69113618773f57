// Texture pipeline (docs/texture.md): ellipsoid fits of texel-sized filtered NDFs (node operator,
// the default, against the exact tent operator), fit_texels end to end, and the separable
// synthesis of a 2048^2 texture, with the random-phase inverse transform measured against a
// brute-force 2-D inverse DFT (one double sum per texel) at a small size.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>

#include "microbrdf/fit.hpp"
#include "microbrdf/generate.hpp"
#include "microbrdf/ndf_estimate.hpp"
#include "microbrdf/texture.hpp"
#include "texture/synthesis_detail.hpp"
#include "texture_test_util.hpp"

using namespace microbrdf;

namespace {

// One 53 um texel (482^2 samples at 110 nm) of the stainless #4 preset, filtered (1 um) NDF.
const TabulatedNdf& texel_ndf() {
  static const TabulatedNdf t = [] {
    BrushedParams p = brushed_preset("stainless4");
    p.nx = p.ny = 482;
    p.seed = 5;
    NdfEstimateOptions o;
    o.resolution = 129;
    return estimate_ndf(generate_brushed(p), o);
  }();
  return t;
}

void texel_fit(benchmark::State& state, FitSampling smp) {
  FitOptions o;
  o.sampling = smp;
  o.threads = 1;
  FitResult r;
  for (auto _ : state) {
    r = fit_ndf(texel_ndf(), o);
    benchmark::DoNotOptimize(r.iterations);
  }
  state.counters["fits_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  const double ay = r.params.at("alpha_y"), tx = r.params.at("theta_x");
  state.counters["lm_iterations"] = static_cast<double>(r.iterations);
  state.counters["alpha_y"] = ay;
  state.counters["theta_x"] = tx;
}
void BM_TexelFit_Node(benchmark::State& s) { texel_fit(s, FitSampling::Node); }
void BM_TexelFit_TentReference(benchmark::State& s) { texel_fit(s, FitSampling::Tent); }
BENCHMARK(BM_TexelFit_Node)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TexelFit_TentReference)->Unit(benchmark::kMillisecond)->Iterations(2);

// End to end: filtered normals of a 964 x 482 scan + 2 texel fits (all threads).
void BM_FitTexels_Scan(benchmark::State& state) {
  BrushedParams p = brushed_preset("stainless4");
  p.nx = 964;
  p.ny = 482;
  const Surface s = generate_brushed(p);
  TexelFitOptions o;
  ParamTexture t;
  for (auto _ : state) {
    t = fit_texels(s, o);
    benchmark::DoNotOptimize(t.channel[0].data());
  }
  state.counters["texels_per_s"] = benchmark::Counter(
      static_cast<double>(state.iterations() * t.size()), benchmark::Counter::kIsRate);
  state.counters["samples_per_s"] = benchmark::Counter(
      static_cast<double>(state.iterations() * s.size()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_FitTexels_Scan)->Unit(benchmark::kMillisecond)->Iterations(2);

// Dong's exemplars: a 100 x 1 strip along and a 1 x 100 strip across.
ParamTexture strip(std::size_t nx, std::size_t ny, std::uint64_t seed) {
  return test_util::gaussian_param_texture(nx, ny, nx > 1 ? 6 : 1, ny > 1 ? 3 : 1,
                                           {0.002, 0.04, 0.01, 0.002, 0.006}, seed, true);
}

void BM_Synthesize(benchmark::State& state) {
  const ParamTexture along = strip(100, 1, 1), across = strip(1, 100, 9);
  SynthesisOptions o;
  o.size = static_cast<std::size_t>(state.range(0));
  for (auto _ : state) {
    const ParamTexture t = synthesize_texture(along, across, o);
    benchmark::DoNotOptimize(t.channel[0].data());
  }
  state.counters["texels_per_s"] = benchmark::Counter(
      static_cast<double>(state.iterations() * o.size * o.size), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Synthesize)->Arg(256)->Arg(2048)->Unit(benchmark::kMillisecond);

// One channel's random-phase inverse transform: FFTW against the direct double sum.
void phase_field(benchmark::State& state, bool direct) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const std::vector<double> amp(n * (n / 2 + 1), 1.0);
  for (auto _ : state) {
    auto f = detail::random_phase_field(amp, n, n, 1, 0, direct);
    benchmark::DoNotOptimize(f.data());
  }
  state.counters["texels_per_s"] = benchmark::Counter(
      static_cast<double>(state.iterations() * n * n), benchmark::Counter::kIsRate);
}
void BM_PhaseField_Fft(benchmark::State& s) { phase_field(s, false); }
void BM_PhaseField_DirectDft(benchmark::State& s) { phase_field(s, true); }
BENCHMARK(BM_PhaseField_Fft)->Arg(64)->Arg(2048)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PhaseField_DirectDft)->Arg(64)->Unit(benchmark::kMillisecond);

}  // namespace
