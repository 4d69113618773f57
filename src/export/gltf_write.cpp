// glTF 2.0 files of a material (include/microbrdf/gltf_export.hpp, docs/gltf.md): the JSON
// document, its binary buffer, and the .glb container (glTF 2.0 spec, "Binary glTF Layout":
// a 12-byte header magic/version/length, a JSON chunk padded with spaces and a BIN chunk padded
// with zeros, each to 4 bytes).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "export/gltf_mesh.hpp"
#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/gltf_export.hpp"
#include "microbrdf/image.hpp"
#include "microbrdf/memory_budget.hpp"

namespace microbrdf {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// glTF enums (spec, "Properties Reference").
constexpr int kFloat = 5126, kUint32 = 5125;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;
constexpr int kNearest = 9728, kLinearMipmapLinear = 9987, kRepeat = 10497;

/// The binary buffer and the bufferViews / accessors that index it.
struct Buffer {
  std::vector<std::uint8_t> bytes;
  json views = json::array(), accessors = json::array();

  int view(const void* data, std::size_t n, int target) {
    bytes.resize((bytes.size() + 3) / 4 * 4, 0);  // every view starts 4-byte aligned
    json v = {{"buffer", 0}, {"byteOffset", bytes.size()}, {"byteLength", n}};
    if (target) v["target"] = target;
    const auto* p = static_cast<const std::uint8_t*>(data);
    bytes.insert(bytes.end(), p, p + n);
    views.push_back(v);
    return int(views.size()) - 1;
  }
  int floats(const std::vector<float>& v, int comps, const char* type, bool bounds) {
    json a = {{"bufferView", view(v.data(), v.size() * 4, kArrayBuffer)},
              {"componentType", kFloat},
              {"count", v.size() / comps},
              {"type", type}};
    if (bounds) {  // required for POSITION; the float values themselves, so they match exactly
      std::vector<float> lo(comps, INFINITY), hi(comps, -INFINITY);
      for (std::size_t i = 0; i < v.size(); ++i) {
        lo[i % comps] = std::min(lo[i % comps], v[i]);
        hi[i % comps] = std::max(hi[i % comps], v[i]);
      }
      a["min"] = lo;
      a["max"] = hi;
    }
    accessors.push_back(a);
    return int(accessors.size()) - 1;
  }
  int indices(const std::vector<std::uint32_t>& v) {
    accessors.push_back({{"bufferView", view(v.data(), v.size() * 4, kElementArrayBuffer)},
                         {"componentType", kUint32},
                         {"count", v.size()},
                         {"type", "SCALAR"}});
    return int(accessors.size()) - 1;
  }
};

json mesh_json(const detail::GltfMesh& m, Buffer& b) {
  json attributes = {{"POSITION", b.floats(m.position, 3, "VEC3", true)},
                     {"NORMAL", b.floats(m.normal, 3, "VEC3", false)},
                     {"TANGENT", b.floats(m.tangent, 4, "VEC4", false)},
                     {"TEXCOORD_0", b.floats(m.uv, 2, "VEC2", false)}};
  return {{"name", m.name},
          {"primitives", json::array({{{"attributes", attributes},
                                       {"indices", b.indices(m.index)},
                                       {"material", 0},
                                       {"mode", 4}}})}};
}

std::uint8_t unorm8(double x) { return std::uint8_t(std::lround(std::clamp(x, 0.0, 1.0) * 255)); }

/// The two texture images and the factors they are scaled by (docs/gltf.md): metallicRoughness
/// G = roughness / roughnessFactor, B = metallic 1; anisotropy RG = (cos, sin) of the direction
/// mapped to [0, 1], B = strength / anisotropyStrength.
struct TextureImages {
  RgbImage roughness, anisotropy;
  double roughness_factor = 1, strength_factor = 0;
};

TextureImages texture_images(const GltfTextureMaps& t, const std::string& path) {
  // The per-texel parameters and two RGB images, before anything is allocated.
  check_memory(path, mul_sat(t.texel.size(), sizeof(GltfAnisotropy) + 6), "the glTF textures");
  std::vector<GltfAnisotropy> g(t.texel.size());
  TextureImages out;
  out.roughness_factor = 0;
  for (std::size_t i = 0; i < g.size(); ++i) {
    g[i] = gltf_anisotropy(t.texel[i]);
    out.roughness_factor = std::max(out.roughness_factor, g[i].roughness);
    out.strength_factor = std::max(out.strength_factor, g[i].strength);
  }
  out.roughness = RgbImage(t.nx, t.ny);
  out.anisotropy = RgbImage(t.nx, t.ny);
  for (std::size_t iy = 0; iy < t.ny; ++iy)
    for (std::size_t ix = 0; ix < t.nx; ++ix) {
      const auto& a = g[ix + t.nx * iy];
      out.roughness.set(ix, iy, 255, unorm8(a.roughness / out.roughness_factor), 255);
      const double s = out.strength_factor > 0 ? a.strength / out.strength_factor : 0.0;
      out.anisotropy.set(ix, iy, unorm8((std::cos(a.rotation) + 1) / 2),
                         unorm8((std::sin(a.rotation) + 1) / 2), unorm8(s));
    }
  return out;
}

json texture_info(int index, double uv_scale) {
  json ti = {{"index", index}};
  ti["extensions"]["KHR_texture_transform"] = {{"scale", {uv_scale, uv_scale}}};
  return ti;
}

/// A positive, finite uv scale or InputError.
void check_options(const GltfExportOptions& o) {
  if (!(o.uv_scale > 0 && std::isfinite(o.uv_scale)))
    throw InputError("glTF: the uv scale must be positive and finite");
  if (o.sphere_segments < 3 || o.sphere_rings < 2 || o.sphere_segments > 4096 ||
      o.sphere_rings > 4096)
    throw InputError("glTF: sphere tessellation must lie in 3..4096 x 2..4096");
}

std::vector<std::uint8_t> glb(const std::string& json_text, const std::vector<std::uint8_t>& bin) {
  const auto pad4 = [](std::size_t n) { return (n + 3) / 4 * 4; };
  const std::size_t jlen = pad4(json_text.size()), blen = pad4(bin.size());
  const std::size_t total = 12 + 8 + jlen + 8 + blen;
  if (total > 0xFFFFFFFFu) throw InputError("glTF: the .glb would exceed 4 GiB");
  std::vector<std::uint8_t> out;
  out.reserve(total);
  const auto u32 = [&](std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(std::uint8_t(v >> (8 * i)));  // little-endian
  };
  u32(0x46546C67);  // "glTF"
  u32(2);
  u32(std::uint32_t(total));
  u32(std::uint32_t(jlen));
  u32(0x4E4F534A);  // "JSON"
  out.insert(out.end(), json_text.begin(), json_text.end());
  out.resize(20 + jlen, ' ');
  u32(std::uint32_t(blen));
  u32(0x004E4942);  // "BIN\0"
  out.insert(out.end(), bin.begin(), bin.end());
  out.resize(total, 0);
  return out;
}

}  // namespace

std::vector<std::string> write_gltf(const GltfMaterial& m, const std::string& path,
                                    const GltfExportOptions& o) {
  check_options(o);
  const fs::path p(path);
  const bool binary = p.extension() == ".glb";
  if (!binary && p.extension() != ".gltf")
    throw InputError(path + ": a glTF file ends in .glb (binary) or .gltf (JSON + .bin + PNGs)");
  const std::string stem = p.stem().string();
  Buffer b;
  json doc;
  doc["asset"] = {{"version", "2.0"}, {"generator", o.generator}};
  json used = json::array();

  const GltfAnisotropy a = gltf_anisotropy(m.ggx);
  json mat = {{"name", m.name}};
  json pbr = {{"baseColorFactor", {m.base_color[0], m.base_color[1], m.base_color[2], 1.0}},
              {"metallicFactor", 1.0},
              {"roughnessFactor", a.roughness}};
  json aniso = {{"anisotropyStrength", a.strength}, {"anisotropyRotation", a.rotation}};
  std::vector<std::pair<std::string, std::vector<std::uint8_t>>> images;  // file name, PNG
  if (!m.texture.empty()) {
    const TextureImages ti = texture_images(m.texture.front(), path);
    images.emplace_back(stem + "_roughness.png", encode_png(ti.roughness, path));
    images.emplace_back(stem + "_anisotropy.png", encode_png(ti.anisotropy, path));
    pbr["roughnessFactor"] = ti.roughness_factor;
    pbr["metallicRoughnessTexture"] = texture_info(0, o.uv_scale);
    aniso = {{"anisotropyStrength", ti.strength_factor},
             {"anisotropyRotation", 0.0},
             {"anisotropyTexture", texture_info(1, o.uv_scale)}};
    doc["samplers"] = json::array({{{"magFilter", kNearest},
                                    {"minFilter", kLinearMipmapLinear},
                                    {"wrapS", kRepeat},
                                    {"wrapT", kRepeat}}});
    doc["textures"] = json::array();
    doc["images"] = json::array();
    for (std::size_t i = 0; i < images.size(); ++i) {
      doc["textures"].push_back({{"sampler", 0}, {"source", i}});
      json img = {{"name", images[i].first}};
      if (binary) {
        img["bufferView"] = b.view(images[i].second.data(), images[i].second.size(), 0);
        img["mimeType"] = "image/png";
      } else {
        img["uri"] = images[i].first;
      }
      doc["images"].push_back(img);
    }
    used.push_back("KHR_texture_transform");
  }
  mat["pbrMetallicRoughness"] = pbr;
  // An isotropic material without a texture needs no extension.
  if (!m.texture.empty() || a.strength > 0) {
    mat["extensions"]["KHR_materials_anisotropy"] = aniso;
    used.push_back("KHR_materials_anisotropy");
  }
  doc["materials"] = json::array({mat});
  if (!used.empty()) doc["extensionsUsed"] = used;

  doc["meshes"] = json::array({mesh_json(detail::gltf_sphere(o.sphere_segments, o.sphere_rings), b),
                               mesh_json(detail::gltf_plate(), b)});
  doc["nodes"] = json::array({{{"name", "sphere"}, {"mesh", 0}}, {{"name", "plate"}, {"mesh", 1}}});
  doc["scenes"] =
      json::array({{{"name", "sphere"}, {"nodes", {0}}}, {{"name", "plate"}, {"nodes", {1}}}});
  doc["scene"] = 0;
  doc["bufferViews"] = b.views;
  doc["accessors"] = b.accessors;
  json buffer = {{"byteLength", b.bytes.size()}};
  if (!binary) buffer["uri"] = stem + ".bin";
  doc["buffers"] = json::array({buffer});
  // What the file is and what glTF could not hold, for a reader of the file.
  doc["extras"]["microbrdf"] = {
      {"source", m.describe},
      {"ggx", {{"alpha_x", m.ggx.alpha_x}, {"alpha_y", m.ggx.alpha_y}, {"phi_rad", m.ggx.phi}}},
      {"warnings", m.warnings}};

  const std::string text = doc.dump();
  std::vector<std::string> files;
  if (binary) {
    write_file_atomic(path, glb(text, b.bytes));
    files.push_back(p.filename().string());
    return files;
  }
  const fs::path dir = p.parent_path();
  write_file_atomic(path, text + "\n");
  files.push_back(p.filename().string());
  write_file_atomic((dir / (stem + ".bin")).string(), b.bytes);
  files.push_back(stem + ".bin");
  for (const auto& [name, png] : images) {
    write_file_atomic((dir / name).string(), png);
    files.push_back(name);
  }
  return files;
}

}  // namespace microbrdf
