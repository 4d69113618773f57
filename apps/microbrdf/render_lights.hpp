#pragma once
// The light flags of `microbrdf render`: --envmap, --env-scale, --env-rotation, --white-env,
// --point, --sphere-light, --disk-light, and the RenderLights they describe.
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "microbrdf/render.hpp"

namespace microbrdf::cli {

struct RenderLightFlags {
  std::string envmap, env_rotation = "0";
  double env_scale = 1;
  bool white_env = false;
  std::vector<std::string> points, sphere_lights, disk_lights;
};

/// Adds the seven flags to `c`, writing into `a`.
void add_render_light_flags(CLI::App* c, RenderLightFlags& a);

/// The lights of the flags; the scene's default light when none is given. InputError for a
/// light that does not parse or has a radius <= 0.
RenderLights make_lights(const RenderLightFlags& a, PreviewScene scene);

}  // namespace microbrdf::cli
