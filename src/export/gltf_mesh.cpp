// The sphere and plate of the glTF export (gltf_mesh.hpp).
#include "export/gltf_mesh.hpp"

#include <cmath>

namespace microbrdf::detail {
namespace {

void vertex(GltfMesh& m, const double p[3], const double t[3], double u, double v) {
  m.position.insert(m.position.end(), {float(p[0]), float(p[1]), float(p[2])});
  m.tangent.insert(m.tangent.end(), {float(t[0]), float(t[1]), float(t[2]), 1.0f});
  m.uv.insert(m.uv.end(), {float(u), float(v)});
}

}  // namespace

GltfMesh gltf_sphere(int segments, int rings) {
  GltfMesh m;
  m.name = "sphere";
  const double repeats = 6 / (2 * M_PI);
  for (int j = 0; j <= rings; ++j) {
    const double lat = -M_PI / 2 + M_PI * j / rings;
    for (int i = 0; i <= segments; ++i) {
      const double lon = 2 * M_PI * i / segments;
      // Poles: cos(lat) is exactly 0 so that every pole vertex lies on the axis.
      const double cl = (j == 0 || j == rings) ? 0.0 : std::cos(lat);
      const double sl = j == 0 ? -1.0 : j == rings ? 1.0 : std::sin(lat);
      const double p[3] = {cl * std::sin(lon), sl, cl * std::cos(lon)};
      const double east[3] = {std::cos(lon), 0, -std::sin(lon)};
      vertex(m, p, east, repeats * lon, repeats * lat);
      m.normal.insert(m.normal.end(), {float(p[0]), float(p[1]), float(p[2])});
    }
  }
  const auto at = [&](int i, int j) { return std::uint32_t(j * (segments + 1) + i); };
  for (int j = 0; j < rings; ++j)
    for (int i = 0; i < segments; ++i) {
      // Seen from outside, east (+i) is to the right of north (+j): (a, b, c) counter-clockwise.
      const auto a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      if (j > 0) m.index.insert(m.index.end(), {a, b, c});
      if (j < rings - 1) m.index.insert(m.index.end(), {a, c, d});
    }
  return m;
}

GltfMesh gltf_plate() {
  GltfMesh m;
  m.name = "plate";
  const double x[4] = {-1, 1, 1, -1}, z[4] = {-1, -1, 1, 1};
  const double t[3] = {1, 0, 0};
  for (int k = 0; k < 4; ++k) {
    const double p[3] = {x[k], 0, z[k]};
    vertex(m, p, t, x[k], -z[k]);
    m.normal.insert(m.normal.end(), {0.0f, 1.0f, 0.0f});
  }
  m.index = {0, 2, 1, 0, 3, 2};
  return m;
}

}  // namespace microbrdf::detail
