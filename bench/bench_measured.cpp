// Measured BRDFs at the default sizes: MERL read (parse of a 35 MB table from memory, next to a
// memcpy of the same bytes), Dong eq. 9 on a MERL table (1025^2 nodes, next to the same number
// of MerlBrdf::eval calls alone) and the RGL .bsdf export of a GGX conductor at the
// default grids, isotropic and anisotropic (next to the BRDF evaluations the isotropic export
// makes, alone; the anisotropic one makes 17 times as many).
#include <benchmark/benchmark.h>

#include <cstring>

#include "microbrdf/export.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/measured.hpp"
#include "microbrdf/measured_ndf.hpp"
#include "microbrdf/microfacet_brdf.hpp"

using namespace microbrdf;

namespace {

const MicrofacetBrdf& ggx() {
  static const MicrofacetBrdf b(std::make_shared<GgxDistribution>(0.3),
                                std::make_shared<ConductorFresnel>(constant_index(1.2, 3.5)));
  return b;
}
const std::vector<std::uint8_t>& merl_bytes() {
  static const std::vector<std::uint8_t> b = encode_merl(tabulate_merl(ggx()));
  return b;
}
const MerlBrdf& merl() {
  static const MerlBrdf m(parse_merl(merl_bytes(), "ggx.binary"));
  return m;
}

void BM_MerlRead(benchmark::State& state) {
  const auto& bytes = merl_bytes();
  for (auto _ : state) {
    auto t = parse_merl(bytes, "ggx.binary");
    benchmark::DoNotOptimize(t.rgb.data());
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * bytes.size()));
}
BENCHMARK(BM_MerlRead)->Unit(benchmark::kMillisecond);

void BM_MerlMemcpyCeiling(benchmark::State& state) {
  const auto& bytes = merl_bytes();
  std::vector<std::uint8_t> out(bytes.size());
  for (auto _ : state) {
    std::memcpy(out.data(), bytes.data(), bytes.size());
    benchmark::DoNotOptimize(out.data());
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * bytes.size()));
}
BENCHMARK(BM_MerlMemcpyCeiling)->Unit(benchmark::kMillisecond);

void BM_MeasuredNdfMerl(benchmark::State& state) {
  const auto& m = merl();
  const ConductorFresnel f(constant_index(1.2, 3.5));
  EffectiveNdfOptions o;  // 1025^2, theta_d 14.14 deg, G = 1
  for (auto _ : state) {
    auto t = effective_ndf(m, f, o);
    benchmark::DoNotOptimize(t.values().data());
  }
  state.counters["nodes/s"] = benchmark::Counter(
      static_cast<double>(state.iterations()) * 1025.0 * 1025.0, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_MeasuredNdfMerl)->Unit(benchmark::kMillisecond)->UseRealTime();

// The MERL lookups alone (same count, one thread): the floor of the eq. 9 pass.
void BM_MerlEvalReference(benchmark::State& state) {
  const auto& m = merl();
  const Vec3 wi(0.1, 0.12, 0.987), wo(-0.05, -0.1, 0.99);
  const std::size_t n = 1025 * 1025;
  for (auto _ : state) {
    double s = 0;
    for (std::size_t i = 0; i < n; ++i) s += m.eval(wi, wo, 550e-9 + 1e-15 * double(i & 7));
    benchmark::DoNotOptimize(s);
  }
  state.counters["evals/s"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * n, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_MerlEvalReference)->Unit(benchmark::kMillisecond);

void BM_ExportBsdfIsotropicGgx(benchmark::State& state) {
  const GgxDistribution d(0.3);
  const RglExportOptions o;  // defaults: 24 theta_i, 64 x 64 ndf grid, 32^2 samples, 25 wavelengths
  for (auto _ : state) {
    auto t = rgl_tensor(ggx(), d, o);
    benchmark::DoNotOptimize(t.fields.data());
  }
  state.counters["brdf_evals/s"] = benchmark::Counter(
      static_cast<double>(state.iterations()) * 24 * 32 * 32 * 25, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ExportBsdfIsotropicGgx)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ExportBsdfAnisotropicGgx(benchmark::State& state) {
  static const MicrofacetBrdf b(std::make_shared<GgxDistribution>(0.1, 0.3),
                                std::make_shared<ConductorFresnel>(constant_index(1.2, 3.5)));
  const GgxDistribution d(0.1, 0.3);
  RglExportOptions o;  // defaults: 17 phi_i x 24 theta_i, 64 x 64 ndf grid, 32^2, 25 wavelengths
  o.isotropic = false;
  for (auto _ : state) {
    auto t = rgl_tensor(b, d, o);
    benchmark::DoNotOptimize(t.fields.data());
  }
  state.counters["brdf_evals/s"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * 17 * 24 * 32 * 32 * 25,
                         benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ExportBsdfAnisotropicGgx)->Unit(benchmark::kMillisecond)->UseRealTime();

// The export's BRDF evaluations alone (24 x 32^2 x 25, one thread).
void BM_ExportBrdfEvalReference(benchmark::State& state) {
  const Vec3 wi(0.3, 0, 0.954), wo(-0.25, 0.05, 0.967);
  const std::size_t n = 24 * 32 * 32 * 25;
  for (auto _ : state) {
    double s = 0;
    for (std::size_t i = 0; i < n; ++i) s += ggx().eval(wi, wo, 400e-9 + 1e-9 * double(i % 25));
    benchmark::DoNotOptimize(s);
  }
  state.counters["brdf_evals/s"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * n, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ExportBrdfEvalReference)->Unit(benchmark::kMillisecond);

}  // namespace
