#pragma once
// `predict`: the choice of the filter sigma (--filter-sigma auto) and the NDF comparison: naive,
// filtered and D_K side by side with their pairwise Hellinger distances (filter_sigma_auto.hpp),
// which one the renders use and why.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "microbrdf/filter_sigma_auto.hpp"
#include "report/predict_stages.hpp"

namespace microbrdf::report {

/// With PredictOptions::filter_sigma_auto, the sweep over the scans (read and levelled on the
/// calling rank; every rank runs it, so all agree on the sigma); nullopt otherwise.
std::optional<FilterSigmaAuto> filter_sigma_sweep(
    const PredictOptions& o, const std::vector<std::string>& paths,
    const std::function<void(const std::string&)>& log);

/// Writes the sweep's curve (filter_sigma_curve.csv and img/filter_sigma_curve.svg) and returns
/// the "ndf_comparison" object: the tables compared, their rms slopes and pairwise Hellinger
/// distances, the NDF of the renders and why, and the sweep. Warns when D_K is nearer another
/// NDF than the one the renders use.
nlohmann::json stage_ndf_comparison(const Context& c, const NdfSet& ndfs,
                                    const FilterSigmaAuto* sweep);

/// The report's section for summary["ndf_comparison"] ("" when the summary has none).
std::string ndf_comparison_html(const nlohmann::json& summary, const std::string& dir);

}  // namespace microbrdf::report
