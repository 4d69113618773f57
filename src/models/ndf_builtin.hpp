#pragma once
// What the built-in NDF models (one file each, src/models/ndf_<name>.cpp, registered in
// src/models/ndf_model.cpp) share.
#include <memory>
#include <nlohmann/json.hpp>
#include <vector>

#include "microbrdf/ndf_model.hpp"

namespace microbrdf {

/// (alpha_x, alpha_y, phi) of the mirror-symmetric anisotropic models.
const std::vector<NdfParam>& anisotropic_params();
/// Their fit JSON: the values plus the ellipsoid-convention keys older files carry
/// (theta_x = theta_y = 0, theta_z = -phi).
nlohmann::json legacy_anisotropic_json(const std::vector<double>& v);

}  // namespace microbrdf
