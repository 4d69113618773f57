#pragma once
// Materials for real-time viewers: glTF 2.0 (docs/gltf.md). A metallic-roughness material with
// KHR_materials_anisotropy on a UV sphere and a plate, as one binary `.glb` or as `.gltf` + `.bin`
// + PNG textures.
//
// The mapping (KHR_materials_anisotropy, "Anisotropy"): glTF's anisotropic GGX has the alpha
// roughness alpha_t = mix(r^2, 1, s^2) along the anisotropy direction (the tangent turned by
// anisotropyRotation counter-clockwise towards the bitangent) and alpha_b = r^2 across it, with
// r = roughness and s = anisotropyStrength. A GGX distribution with widths alpha_x, alpha_y
// (alpha_x along azimuth phi from the tangent, the surface's x axis) is therefore, exactly when
// both widths are at most 1:
//   r = sqrt(min(alpha_x, alpha_y)),  s = sqrt((a_max - a_min) / (1 - a_min)),
//   rotation = the azimuth of the wider axis, folded into (-pi/2, pi/2].
// Mesh frame: TANGENT = the material's x axis (+u), bitangent = normal x tangent (w = +1) = its
// y axis (+v), as the scan's (x, y, n) frame is right-handed.

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "microbrdf/brdf_spec.hpp"
#include "microbrdf/material_spec.hpp"
#include "microbrdf/microfacet.hpp"

namespace microbrdf {

/// The KHR_materials_anisotropy parameters of a GGX distribution (all dimensionless, rotation in
/// rad).
struct GltfAnisotropy {
  double roughness = 1;  ///< pbrMetallicRoughness.roughnessFactor, in [0, 1]
  double strength = 0;   ///< anisotropyStrength, in [0, 1]
  double rotation = 0;   ///< anisotropyRotation, rad, in (-pi/2, pi/2]
};

/// The glTF parameters of the GGX widths `a` (header comment). Widths above 1 (which glTF cannot
/// hold) are clamped to 1 and `clamped` is set. Throws InputError for widths that are not
/// positive and finite.
GltfAnisotropy gltf_anisotropy(const AnisotropicAlpha& a, bool* clamped = nullptr);
/// The inverse: alpha_x = mix(r^2, 1, s^2) along phi = rotation, alpha_y = r^2.
AnisotropicAlpha ggx_from_gltf(const GltfAnisotropy& g);

/// Per-texel GGX widths of a parameter texture (texture.hpp), row-major, iy = 0 first.
struct GltfTextureMaps {
  std::size_t nx = 0, ny = 0;
  std::vector<AnisotropicAlpha> texel;
};

/// A material as glTF holds it.
struct GltfMaterial {
  std::string name = "microbrdf";
  std::string describe;                       ///< the source BRDF and material, one line
  std::array<double, 3> base_color{1, 1, 1};  ///< linear sRGB normal-incidence reflectance, [0, 1]
  AnisotropicAlpha ggx;                  ///< the uniform GGX widths (a texture: its mean texel)
  std::vector<GltfTextureMaps> texture;  ///< empty, or one parameter texture's per-texel widths
  /// What glTF cannot represent for this material, one sentence each (with the error made).
  std::vector<std::string> warnings;
};

/// The glTF material of a BRDF spec and its material (docs/gltf.md): the GGX widths of an
/// analytic GGX as they are; Beckmann, the ellipsoid (a texture's mean texel too), a tabulated
/// NDF, Kirchhoff, Sun 2002 and SH BRDFs through a GGX fit (of the distribution tabulated on
/// 257^2 nodes, or of the BRDF's eq. 9 lobe), with its Hellinger distance in the warnings; the
/// base colour of the material's normal-incidence reflectance under D65 (as `brdf color`),
/// clipped to [0, 1]; warnings for the Fresnel term (glTF's Schlick with F0 = base colour: the
/// largest difference over 0-89 deg), the shadowing form and anything clamped. A texture spec
/// also fills `texture` (each texel's ellipsoid without its tilts: GGX with phi = -theta_z).
/// Throws InputError for a Lambertian BRDF, an ideal mirror or a dielectric (no metallic
/// equivalent), FileError for unreadable files.
GltfMaterial gltf_material(const BrdfSpec& spec, const MaterialSpec& material);

struct GltfExportOptions {
  /// Texture repeats per scene unit (as `render --uv-scale`): KHR_texture_transform scale.
  double uv_scale = 1;
  int sphere_segments = 64, sphere_rings = 32;  ///< UV sphere tessellation
  std::string generator = "microbrdf";
};

/// Writes the material on a unit UV sphere (scene 0, "sphere") and a 2 x 2 plate in the xz plane
/// facing +y (scene 1, "plate"): `path` ending in .glb gives one binary file; .gltf gives
/// `path`, `<stem>.bin` and, for a texture, `<stem>_roughness.png` and `<stem>_anisotropy.png`
/// beside it. Returns the file names written (without directories). All files are written
/// atomically, together. Throws InputError for another extension, FileError for write errors.
std::vector<std::string> write_gltf(const GltfMaterial& m, const std::string& path,
                                    const GltfExportOptions& options = {});

}  // namespace microbrdf
