#pragma once
// The built-in NDF models, one file each (src/models/ndf_<name>.cpp), registered in
// src/models/ndf_model.cpp.
#include <memory>
#include <nlohmann/json.hpp>
#include <vector>

#include "microbrdf/ndf_model.hpp"

namespace microbrdf {

std::unique_ptr<NdfModel> make_ellipsoid_model();
std::unique_ptr<NdfModel> make_beckmann_model();
std::unique_ptr<NdfModel> make_ggx_model();
std::unique_ptr<NdfModel> make_student_t_model();

}  // namespace microbrdf

namespace microbrdf {

/// (alpha_x, alpha_y, phi) of the mirror-symmetric anisotropic models.
const std::vector<NdfParam>& anisotropic_params();
/// Their fit JSON: the values plus the ellipsoid-convention keys older files carry
/// (theta_x = theta_y = 0, theta_z = -phi).
nlohmann::json legacy_anisotropic_json(const std::vector<double>& v);

}  // namespace microbrdf
