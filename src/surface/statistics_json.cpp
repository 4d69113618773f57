// SurfaceStats as JSON: one layout for `info --json`, `generate --json`, predict's summary.json
// and the Python module's statistics().
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

nlohmann::json stats_json(const std::string& path, const Surface& s, const SurfaceStats& st) {
  nlohmann::json j = stats_json(st);
  j["path"] = path;
  j["format"] = s.meta.format;
  j["invalid_count"] = s.size() - st.valid_count;
  j["leveling"] = s.meta.leveling;
  j["z0_m"] = s.z0;
  j["instrument"] = s.meta.instrument;
  j["date"] = s.meta.date;
  j["z_unit_in_file"] = s.meta.z_unit_in_file;
  return j;
}

}  // namespace microbrdf
