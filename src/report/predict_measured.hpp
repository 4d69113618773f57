#pragma once
// `predict --measured FILE`: the prediction against a measurement (Dong 2015 section 7, Figs.
// 8-9). The measured file (a goniometer .csv, a MERL .binary, an RGL .bsdf, or an effective NDF
// table .npy/.exr from `measured ndf`) becomes an effective NDF (Dong eq. 9, G = 1, F = 1: the
// shape), and each predicted NDF (filtered; Kirchhoff D_K when computed) is compared with it
// as `measured compare` does (measured_compare.hpp): convolved with the instrument's Gaussian,
// on the measured nodes only.
#include <nlohmann/json.hpp>
#include <string>

#include "report/predict_stages.hpp"

namespace microbrdf::report {

/// Checks the measured file: it exists, has a known extension and reads (a broken file fails
/// before any scan is read). Throws FileError / InputError.
void check_measured_option(const PredictOptions& o);
/// Writes ndf_measured.npy and measured/<prediction>/ (compare.json, measured.png,
/// predicted.png, slices.csv, slices.png); returns the "measured" object of summary.json.
nlohmann::json stage_measured(const Context& c, const NdfSet& ndfs);
/// The report's section for summary["measured"] ("" when the summary has none). Images are
/// read from `dir` and embedded. Throws FileError when one is missing.
std::string measured_section_html(const nlohmann::json& summary, const std::string& dir);

}  // namespace microbrdf::report
