// Binary readers' throughput (MB/s of file bytes), parsing from memory, next to a memcpy of
// the same bytes (the ceiling any reader can reach) in the same run.
#include <benchmark/benchmark.h>

#include <cstring>
#include <string>
#include <vector>

#include "microbrdf/io.hpp"

using namespace microbrdf;

namespace {

const std::vector<std::uint8_t>* load(const std::string& path) {
  static std::vector<std::pair<std::string, std::vector<std::uint8_t>>> cache;
  for (auto& [p, d] : cache)
    if (p == path) return &d;
  try {
    cache.emplace_back(path, read_file_bytes(path, 1ULL << 30));
  } catch (...) {
    return nullptr;
  }
  return &cache.back().second;
}

void BM_Read(benchmark::State& state, std::string path, SurfaceFormat fmt) {
  auto* data = load(path);
  if (!data) {
    state.SkipWithError(("missing " + path).c_str());
    return;
  }
  ReadOptions opt;
  if (format_needs_spacing(fmt)) opt.dx = opt.dy = 1e-6;
  for (auto _ : state) {
    auto s = read_surface_bytes(*data, fmt, path, opt);
    benchmark::DoNotOptimize(s.z.data());
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * data->size()));
  state.counters["file_MB"] = static_cast<double>(data->size()) / 1e6;
}

void BM_MemcpyCeiling(benchmark::State& state) {
  std::vector<std::uint8_t> a(2'000'000, 1), b(a.size());
  for (auto _ : state) {
    std::memcpy(b.data(), a.data(), a.size());
    benchmark::DoNotOptimize(b.data());
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * a.size()));
}

const std::string kData = MICROBRDF_TEST_DATA;

}  // namespace

BENCHMARK(BM_MemcpyCeiling);
BENCHMARK_CAPTURE(BM_Read, x3p_sample_land, kData + "/sample-land.x3p", SurfaceFormat::X3p)
    ->Unit(benchmark::kMillisecond);
#ifdef MICROBRDF_EXTRA_DATA  // a 4 MB float32 file, only in the optional extra data folder
BENCHMARK_CAPTURE(BM_Read, x3p_ski_float32,
                  std::string(MICROBRDF_EXTRA_DATA) + "/SkiInfiniteFocus.x3p", SurfaceFormat::X3p)
    ->Unit(benchmark::kMillisecond);
#endif
BENCHMARK_CAPTURE(BM_Read, metropro_dat, kData + "/metropro-1.dat", SurfaceFormat::MetroProDat)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Read, datx, kData + "/zygo_test.datx", SurfaceFormat::Datx)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Read, sur, kData + "/sur-2.sur", SurfaceFormat::Sur)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Read, plu, kData + "/plu-1-heights.plu", SurfaceFormat::Plu)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Read, gwy, kData + "/test.gwy", SurfaceFormat::Gwy)
    ->Unit(benchmark::kMillisecond);
