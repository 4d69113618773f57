#pragma once
// Helpers shared by the renderer's tests.
#include <Eigen/Core>

#include "microbrdf/render.hpp"

namespace microbrdf::test {

/// The mean linear sRGB of an image.
inline Eigen::Vector3d mean_rgb(const RenderImage& img) {
  Eigen::Vector3d m = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < img.rgb.size() / 3; ++i)
    m += Eigen::Vector3d(img.rgb[3 * i], img.rgb[3 * i + 1], img.rgb[3 * i + 2]);
  return m / double(img.rgb.size() / 3);
}

}  // namespace microbrdf::test
