// check_scene_geometry: the bounds that keep a micro-scene traceable (microscene.hpp).
#include <algorithm>
#include <cmath>
#include <string>

#include "core/length_text.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/microscene.hpp"

namespace microbrdf {

namespace {
// A tile below 1 nm holds no microgeometry, and its float coordinates would be all round-off.
constexpr double kMinTileSide = 1e-9;
}  // namespace

void check_scene_geometry(const MicroSceneDesc& d) {
  const double W = d.width, H = d.height;
  if (!(W >= kMinTileSide && H >= kMinTileSide && std::isfinite(W) && std::isfinite(H)))
    throw InputError("tile " + detail::format_length_any(W) + " x " + detail::format_length_any(H) +
                     ": both sides must be at least 1 nm");
  const double side = std::min(W, H), reach = kMaxSceneReach * side;
  const std::string bound = "within " + detail::format_length_any(reach) + " (" +
                            std::to_string(static_cast<int>(kMaxSceneReach)) +
                            " x the tile's shorter side " + detail::format_length_any(side) + ")";
  // A value v along an axis whose tile span is [0, span]: finite and within `reach` of it.
  auto near = [&](double v, double span) { return v >= -reach && v <= span + reach; };
  for (std::size_t i = 0; i < d.planes.size(); ++i)
    if (!near(d.planes[i].z, 0))
      throw InputError("plane " + std::to_string(i + 1) +
                       ": z = " + detail::format_length_any(d.planes[i].z) + " must lie " + bound +
                       " of the tile");
  for (std::size_t i = 0; i < d.capsules.size(); ++i) {
    const Capsule& c = d.capsules[i];
    const bool ok = c.radius <= reach && near(c.a.x(), W) && near(c.b.x(), W) && near(c.a.y(), H) &&
                    near(c.b.y(), H) && near(c.a.z() - c.radius, 0) &&
                    near(c.a.z() + c.radius, 0) && near(c.b.z() - c.radius, 0) &&
                    near(c.b.z() + c.radius, 0);
    if (!ok)
      throw InputError(
          "object " + std::to_string(i + 1) + " (radius " + detail::format_length_any(c.radius) +
          ", from (" + detail::format_length_any(c.a.x()) + ", " +
          detail::format_length_any(c.a.y()) + ", " + detail::format_length_any(c.a.z()) +
          ") to (" + detail::format_length_any(c.b.x()) + ", " +
          detail::format_length_any(c.b.y()) + ", " + detail::format_length_any(c.b.z()) +
          ")) reaches beyond the tile: every part must lie " + bound +
          "; check its radius, length and z");
  }
  for (std::size_t i = 0; i < d.heightfields.size(); ++i)
    for (double z : d.heightfields[i].surface.z) {
      if (std::isnan(z))
        throw InputError("height field " + std::to_string(i + 1) +
                         " has invalid (NaN) samples: fill them first");
      if (!near(z, 0))
        throw InputError("height field " + std::to_string(i + 1) + ": height " +
                         detail::format_length_any(z) + " must lie " + bound +
                         "; check its sigma, z_scale and units");
    }
}

}  // namespace microbrdf
