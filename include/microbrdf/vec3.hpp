#pragma once
// The direction type of every model and BRDF: a 3-vector in the local frame of the surface
// (macro normal n = +z, x and y in the surface plane, directions pointing away from it).

#include <Eigen/Core>

namespace microbrdf {

using Vec3 = Eigen::Vector3d;

}  // namespace microbrdf
