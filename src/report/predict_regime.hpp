#pragma once
// `predict`: the report's account of the scattering regime (summary.json "regime"): the theory
// the predicted BRDF uses and why, per incidence, and the regime map.
#include <nlohmann/json.hpp>
#include <string>

namespace microbrdf::report {

/// The report's subsection for summary["regime"] ("" when the summary has none); the map's SVG
/// is read from `dir`.
std::string regime_section_html(const nlohmann::json& summary, const std::string& dir);

}  // namespace microbrdf::report
