#pragma once
// The preview meshes of the glTF export (gltf_export.hpp): vertex arrays as glTF stores them.
#include <cstdint>
#include <string>
#include <vector>

namespace microbrdf::detail {

/// Triangles with per-vertex position, unit normal, unit tangent (xyz, w = +1: bitangent =
/// normal x tangent) and texture coordinates in scene units; counter-clockwise seen from outside.
struct GltfMesh {
  std::string name;
  std::vector<float> position, normal, tangent, uv;  // 3, 3, 4, 2 floats per vertex
  std::vector<std::uint32_t> index;
  std::size_t vertices() const { return position.size() / 3; }
};

/// Unit sphere at the origin, y up: `segments` along the longitude, `rings` along the latitude.
/// u = 6 longitude / (2 pi), v = 6 latitude / (2 pi): whole texture repeats around it (6 per
/// turn, about one per unit of arc), the tangent east, so the bitangent points north.
GltfMesh gltf_sphere(int segments, int rings);
/// The 2 x 2 plate of `render --scene plate`: the xz plane facing +y, u = x, v = -z.
GltfMesh gltf_plate();

}  // namespace microbrdf::detail
