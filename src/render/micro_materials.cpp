// The materials of a micro-scene as the renderer draws them (render.hpp, micro_scene_materials).
#include <memory>

#include "microbrdf/error.hpp"
#include "microbrdf/lambertian_brdf.hpp"
#include "microbrdf/microscene.hpp"
#include "microbrdf/mirror_brdf.hpp"
#include "microbrdf/render.hpp"

namespace microbrdf {

std::vector<std::shared_ptr<const Svbrdf>> micro_scene_materials(const MicroSceneDesc& scene) {
  std::vector<std::shared_ptr<const Svbrdf>> out;
  for (const MicroMaterial& m : scene.materials) {
    std::shared_ptr<const Brdf> b;
    switch (m.kind) {
      case MicroMaterial::Kind::Mirror:
        b = std::make_shared<SpecularMirrorBrdf>(m.fresnel);
        break;
      case MicroMaterial::Kind::Lambert:
        b = std::make_shared<LambertianBrdf>(m.albedo);
        break;
      case MicroMaterial::Kind::Brdf:
        b = m.brdf;
        break;
      case MicroMaterial::Kind::Absorber:
        b = std::make_shared<LambertianBrdf>(0.0);  // reflects nothing: the path ends there
        break;
      case MicroMaterial::Kind::Dielectric:
        throw InputError("micro-scene material '" + m.name +
                         "' is a dielectric (light travels inside it), which the renderer "
                         "does not draw: it renders reflecting materials only");
    }
    if (!b) throw InputError("micro-scene material '" + m.name + "' has no BRDF");
    out.push_back(std::make_shared<UniformSvbrdf>(std::move(b)));
  }
  if (out.empty()) throw InputError("micro-scene: no materials");
  return out;
}

}  // namespace microbrdf
