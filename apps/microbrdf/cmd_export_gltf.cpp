// `microbrdf export gltf`: the material of the BRDF and material flags as glTF 2.0 with
// KHR_materials_anisotropy on a sphere and a plate (docs/gltf.md).
#include <cstdio>
#include <memory>

#include "cli_common.hpp"
#include "commands.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/gltf_export.hpp"
#include "spec_flags.hpp"

namespace microbrdf::cli {
namespace {

struct GltfArgs {
  std::string output;
  SpecFlags spec;
  double uv_scale = 1;
  bool json = false;
};

void run_gltf(const GltfArgs& a) {
  Preflight pre;
  check_spec_files(pre, a.spec);
  pre.output("-o", a.output, {".glb", ".gltf"}).positive("--uv-scale", a.uv_scale);
  pre.done();
  if (a.spec.keys().empty())
    throw InputError(
        "give a BRDF (--model/--alpha, --ndf, --kirchhoff, --sun, --sh, --texture) with its "
        "material");
  const BrdfSpec spec = brdf_spec(a.spec);
  const MaterialSpec material =
      spec.uses_material() ? material_spec(a.spec, std::nullopt) : MaterialSpec{};
  const GltfMaterial m = gltf_material(spec, material);
  for (const auto& w : m.warnings)
    std::fprintf(stderr, "microbrdf export gltf: warning: %s\n", w.c_str());
  GltfExportOptions o;
  o.uv_scale = a.uv_scale;
  const auto files = write_gltf(m, a.output, o);
  const GltfAnisotropy g = gltf_anisotropy(m.ggx);
  if (a.json) {
    nlohmann::json j = {
        {"output", a.output},
        {"files", files},
        {"source", m.describe},
        {"ggx", {{"alpha_x", m.ggx.alpha_x}, {"alpha_y", m.ggx.alpha_y}, {"phi_rad", m.ggx.phi}}},
        {"base_color_linear_srgb", m.base_color},
        {"roughness", g.roughness},
        {"anisotropy_strength", g.strength},
        {"anisotropy_rotation_rad", g.rotation},
        {"warnings", m.warnings}};
    if (!m.texture.empty())
      j["texture"] = {
          {"nx", m.texture.front().nx}, {"ny", m.texture.front().ny}, {"uv_scale", a.uv_scale}};
    print_json(j);
    return;
  }
  std::printf("%s -> %s\n", m.describe.c_str(), a.output.c_str());
  std::printf("  GGX alpha %.6g x %.6g, phi %.4g deg\n", m.ggx.alpha_x, m.ggx.alpha_y,
              m.ggx.phi * 180 / M_PI);
  std::printf("  glTF roughness %.6g, anisotropyStrength %.6g, anisotropyRotation %.6g rad%s\n",
              g.roughness, g.strength, g.rotation,
              m.texture.empty() ? "" : " (the texture's mean texel; per texel in the textures)");
  std::printf("  baseColorFactor %.4f %.4f %.4f (linear sRGB), metallic 1\n", m.base_color[0],
              m.base_color[1], m.base_color[2]);
}

}  // namespace

void register_export_gltf(CLI::App* e) {
  auto a = std::make_shared<GltfArgs>();
  auto* c = e->add_subcommand("gltf",
                              "glTF 2.0 material (KHR_materials_anisotropy) on a sphere "
                              "and a plate, for real-time viewers");
  c->footer(
      "Writes a .glb (one binary file) or a .gltf with its .bin and PNG textures beside it: a\n"
      "metallic-roughness material (metallic 1, baseColorFactor = the material's normal-incidence\n"
      "reflectance in linear sRGB, as `brdf color`) with roughness and KHR_materials_anisotropy\n"
      "from the GGX widths by the extension's definition (docs/gltf.md), on a unit sphere (scene\n"
      "0) and the 2 x 2 plate of `render --scene plate` (scene 1). Beckmann, the ellipsoid, "
      "--ndf,\n"
      "--kirchhoff, --sun and --sh become their GGX fit. A --texture becomes a roughness texture\n"
      "(metallicRoughness G) and an anisotropy texture (RG direction, B strength), repeated\n"
      "--uv-scale times per scene unit (KHR_texture_transform). What glTF cannot represent (its\n"
      "Schlick Fresnel, its GGX shape and Smith term) is said on stderr, in --json and in the\n"
      "file's extras.\n\n"
      "Examples:\n"
      "  microbrdf export gltf --model ggx --alpha-x 0.1 --alpha-y 0.3 --phi 30deg --metal Al "
      "-o al.glb\n"
      "  microbrdf export gltf --model ellipsoid --alpha 0.2 --metal Au -o au.gltf\n"
      "  microbrdf export gltf --texture tex.exr --uv-scale 2 --metal SS-austenitic -o ss.glb");
  add_export_source_flags(c, a->spec);
  c->add_option("-o,--output", a->output, "Output .glb or .gltf")->required();
  c->add_option("--uv-scale", a->uv_scale, "Texture repeats per scene unit")
      ->capture_default_str()
      ->check(positive_number(1e6));
  c->add_flag("--json", a->json, "Print a JSON summary on stdout");
  c->callback([a] { run_guarded("export gltf", [&] { run_gltf(*a); }); });
}

}  // namespace microbrdf::cli
