#pragma once
// Equirectangular environment maps as the renderer reads them, for other layers (the report's
// interactive view) that need the pixels themselves.

#include <string>
#include <vector>

namespace microbrdf {

/// Linear RGB radiance, row-major from the top, 3 floats per pixel. Row 0 is the zenith (+y),
/// the middle column lies straight ahead (-z) (docs/render.md, "Scenes and frames").
struct EnvmapImage {
  int width = 0, height = 0;
  std::vector<float> rgb;
};

/// Reads an OpenEXR (R, G, B or Y) or Radiance .hdr map, chosen by the file's magic number, with
/// the renderer's bounds checks and memory budget. Throws FileError naming the file.
EnvmapImage read_envmap(const std::string& path);

}  // namespace microbrdf
