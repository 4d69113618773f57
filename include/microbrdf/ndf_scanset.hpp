#pragma once
// NDFs of scan sets over all ranks and threads (distribute.hpp; docs/scale.md): each scan is
// read, levelled and estimated on whichever rank takes it, and its share (NdfScanPartial,
// KirchhoffScanPartial) is folded on rank 0 in scan order, so the table is bit-identical for any
// number of ranks and threads.

#include <cstddef>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "microbrdf/distribute.hpp"
#include "microbrdf/io.hpp"
#include "microbrdf/kirchhoff.hpp"
#include "microbrdf/level.hpp"
#include "microbrdf/ndf_estimate.hpp"

namespace microbrdf {

struct ScanSetOptions {
  ReadOptions read;
  LevelingSpec leveling;
  /// Rank 0, as each scan is folded (scan order): index, path and {"nx", "ny", "dx_m", "dy_m",
  /// "leveling"} of the scan (for progress lines and warnings).
  std::function<void(std::size_t, const std::string&, const nlohmann::json&)> on_scan;
  DistributeOptions distribute;
};

/// The geometric NDF accumulator of every scan in `paths`. Rank 0 gets the accumulator (call
/// result()), other ranks nullopt. `stats` (rank 0): scans and seconds per rank.
std::optional<NdfAccumulator> accumulate_ndf_scans(const std::vector<std::string>& paths,
                                                   const NdfEstimateOptions& options,
                                                   const ScanSetOptions& set,
                                                   WorkStats* stats = nullptr);

/// The same for the Kirchhoff D_K. options.progress (per patch of a scan) is called only when
/// the run has a single rank, with the fraction of the whole set done.
std::optional<KirchhoffAccumulator> accumulate_kirchhoff_scans(
    const std::vector<std::string>& paths, const KirchhoffOptions& options,
    const ScanSetOptions& set, WorkStats* stats = nullptr);

/// A scan's share as sent between ranks (exact: doubles travel bit for bit; only the rows of
/// the table that hold a non-zero value are sent), and back.
WorkResult pack_partial(const NdfScanPartial& p, const nlohmann::json& scan_info);
NdfScanPartial unpack_ndf_partial(const WorkResult& r, std::size_t resolution);
WorkResult pack_partial(const KirchhoffScanPartial& p, const nlohmann::json& scan_info);
KirchhoffScanPartial unpack_kirchhoff_partial(const WorkResult& r, std::size_t resolution);

}  // namespace microbrdf
