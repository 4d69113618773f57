// What rank 0 pays per scan when a scan set is spread over MPI ranks (docs/scale.md, "Cost
// model"), next to the work one scan costs a rank, in the same run: the filtered NDF share of a
// 640 x 480 scan at 110 nm (the per-scan work), and packing, unpacking and folding that share on
// a 1025^2 table (rank 0's serial part per scan). Plus the work queue's own cost per item in one
// process (empty items).
#include <benchmark/benchmark.h>

#include "microbrdf/distribute.hpp"
#include "microbrdf/generate.hpp"
#include "microbrdf/ndf_estimate.hpp"
#include "microbrdf/ndf_scanset.hpp"
#include "surface_test_util.hpp"

using namespace microbrdf;

namespace {

// Dong's scan size: 640 x 480 at 110 nm.
const Surface& scan() {
  static const Surface s = test_util::isotropic_gaussian(640, 480, 110e-9, 0.1e-6, 1e-6);
  return s;
}

NdfEstimateOptions filtered() {
  NdfEstimateOptions o;
  o.method = NdfMethod::Filtered;
  o.resolution = 1025;
  return o;
}

// The per-scan work of `ndf --method filtered` (any rank).
void BM_ScanShareFiltered(benchmark::State& state) {
  const NdfAccumulator acc(filtered());
  for (auto _ : state) benchmark::DoNotOptimize(acc.estimate(scan()));
  state.counters["scans/s"] = benchmark::Counter(1, benchmark::Counter::kIsIterationInvariantRate);
}

// Rank 0's serial part per scan: the share as sent (pack), received (unpack) and folded in.
void BM_ScanShareFold(benchmark::State& state) {
  NdfAccumulator acc(filtered());
  const NdfScanPartial share = acc.estimate(scan());
  const WorkResult sent = pack_partial(share, nlohmann::json::object());
  for (auto _ : state) {
    WorkResult w = pack_partial(share, nlohmann::json::object());
    acc.merge(unpack_ndf_partial(w, 1025));
  }
  state.counters["bytes/scan"] =
      static_cast<double>(sent.values.size() * sizeof(double) + sent.text.size());
  state.counters["scans/s"] = benchmark::Counter(1, benchmark::Counter::kIsIterationInvariantRate);
}

// The queue itself: items that do nothing, one process, one worker thread.
void BM_DistributeEmptyItems(benchmark::State& state) {
  const std::size_t n = 1000;
  for (auto _ : state) {
    std::size_t sum = 0;
    distribute(
        n,
        [](std::size_t i) {
          WorkResult r;
          r.values = {static_cast<double>(i)};
          return r;
        },
        [&](std::size_t, WorkResult&& r) { sum += static_cast<std::size_t>(r.values[0]); });
    benchmark::DoNotOptimize(sum);
  }
  state.counters["items/s"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

BENCHMARK(BM_ScanShareFiltered)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ScanShareFold)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DistributeEmptyItems)->Unit(benchmark::kMillisecond);
