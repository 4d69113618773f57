// Render options from their command-line and Python spellings, and the default light
// (render.hpp).
#include <sstream>

#include "microbrdf/error.hpp"
#include "microbrdf/render.hpp"
#include "render/direct_ris.hpp"

namespace microbrdf {

MisMode parse_mis_mode(const std::string& name, const std::string& flag) {
  if (name == "mis") return MisMode::Mis;
  if (name == "brdf") return MisMode::BrdfOnly;
  if (name == "light") return MisMode::LightOnly;
  throw InputError(flag + " '" + name + "': give mis, brdf or light");
}

void add_default_light_if_none(RenderLights& l, PreviewScene scene) {
  const bool none = l.envmap_path.empty() && !l.uniform_white_env && l.points.empty() &&
                    l.spheres.empty() && l.disks.empty();
  if (none && scene == PreviewScene::Plate)
    l.disks.push_back(dong_plate_light());
  else if (none)
    l.uniform_white_env = true;
}

void parse_ris_candidates(const std::string& text, const std::string& flag,
                          RenderOptions& options) {
  std::istringstream is(text);
  int m = 0, n = 0;
  char comma = 0;
  if (!(is >> m >> comma >> n) || comma != ',' || !(is >> std::ws).eof() || m < 1 ||
      m > pt::kMaxRisBrdfCandidates || n < 1 || n > pt::kMaxRisLightCandidates)
    throw InputError(flag + " '" + text + "': give M,N (BRDF, light candidates), M in 1.." +
                     std::to_string(pt::kMaxRisBrdfCandidates) + ", N in 1.." +
                     std::to_string(pt::kMaxRisLightCandidates));
  options.ris_brdf_candidates = m;
  options.ris_light_candidates = n;
}

}  // namespace microbrdf
