#pragma once
// A toy NDF model added through the registry alone (docs/architecture.md, "How to add a
// reflectance model"): this header, toy_ndf.cpp and the one line that registers it.
#include <memory>

#include "microbrdf/ndf_model.hpp"

namespace microbrdf::toy {

/// "toy": isotropic GGX with one parameter `roughness` (--roughness): D = 1 / (pi r^2 (|m_xy|^2
/// / r^2 + m_z^2)^2).
std::unique_ptr<NdfModel> make_toy_model();

}  // namespace microbrdf::toy
