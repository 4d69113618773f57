// SurfaceStats as JSON: one layout for `info --json`, `generate --json` and predict's
// summary.json.
#include <cmath>
#include <nlohmann/json.hpp>

#include "microbrdf/statistics.hpp"

namespace microbrdf {
namespace {

nlohmann::json number_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

}  // namespace

nlohmann::json stats_json(const SurfaceStats& st) {
  return {{"nx", st.nx},
          {"ny", st.ny},
          {"dx_m", st.dx},
          {"dy_m", st.dy},
          {"valid_count", st.valid_count},
          {"valid_fraction", st.valid_fraction},
          {"mean_m", st.mean},
          {"min_m", st.min},
          {"max_m", st.max},
          {"sq_m", st.sq},
          {"sa_m", st.sa},
          {"skewness", st.skewness},
          {"kurtosis", st.kurtosis},
          {"slope_rms_x", st.slope_rms_x},
          {"slope_rms_y", st.slope_rms_y},
          {"corr_length_x_m", number_or_null(st.corr_length_x)},
          {"corr_length_y_m", number_or_null(st.corr_length_y)},
          {"corr_length_m", number_or_null(st.corr_length)}};
}

}  // namespace microbrdf
