#pragma once
// `predict`: the energy single scattering loses on the measured NDF, and whether the comparison
// strip shows the multiple-scattering BRDF (PredictOptions::multiple_scattering).
#include <nlohmann/json.hpp>
#include <string>

#include "report/predict_stages.hpp"

namespace microbrdf::report {

/// The geometric NDF the multiple-scattering BRDF uses: the run's render table when it is the
/// naive one, else the filtered.
const TabulatedNdf& ms_table_of(const NdfSet& ndfs);
/// Its name: "naive" or "filtered".
std::string ms_table_name(const NdfSet& ndfs);
/// Directional energy of orders >= 2 with F = 1 at theta_i 0, 20, 40, 60, 70, 80 deg, light along
/// the table's x and y axes (4000 random walks each, fixed streams), and the decision for the
/// comparison strip ("auto": shown when the loss exceeds 2 % at some theta_i <= 70 deg). Returns
/// the "multiple_scattering" object.
nlohmann::json stage_energy_loss(const Context& c, const NdfSet& ndfs);
/// The report's subsection for summary["multiple_scattering"] ("" without one).
std::string energy_loss_html(const nlohmann::json& summary);

}  // namespace microbrdf::report
