// glTF export (include/microbrdf/gltf_export.hpp): the files are read back by a reader written
// here from the glTF 2.0 spec (GLB container, JSON, accessors, PNG through libpng), and the GGX
// widths are recovered from what was written by KHR_materials_anisotropy's definition, written
// here again: alpha_t = mix(r^2, 1, s^2) along the rotated tangent, alpha_b = r^2.
#include <gtest/gtest.h>
#include <png.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>

#include "microbrdf/error.hpp"
#include "microbrdf/gltf_export.hpp"
#include "microbrdf/texture.hpp"

namespace fs = std::filesystem;
using nlohmann::json;
using namespace microbrdf;

namespace {

std::vector<std::uint8_t> slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

std::uint32_t le32(const std::uint8_t* p) {
  return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 |
         std::uint32_t(p[3]) << 24;
}

/// A glTF asset as read back: its JSON and the bytes of buffer 0 (.glb BIN chunk or .bin file).
struct Asset {
  json doc;
  std::vector<std::uint8_t> bin;
  fs::path dir;
  std::vector<std::uint8_t> view(int i) const {
    const json& v = doc["bufferViews"][i];
    const std::size_t off = v.value("byteOffset", 0), n = v["byteLength"];
    EXPECT_LE(off + n, bin.size());
    return {bin.begin() + off, bin.begin() + off + n};
  }
  /// An image's PNG bytes, embedded or beside the file.
  std::vector<std::uint8_t> image(int i) const {
    const json& im = doc["images"][i];
    if (im.contains("bufferView")) return view(im["bufferView"]);
    return slurp(dir / im["uri"].get<std::string>());
  }
};

Asset read_asset(const fs::path& path) {
  Asset a;
  a.dir = path.parent_path();
  const auto bytes = slurp(path);
  if (path.extension() == ".glb") {
    // Header: magic "glTF", version 2, total length; then chunks of (length, type, data).
    EXPECT_GE(bytes.size(), 28u);
    EXPECT_EQ(std::memcmp(bytes.data(), "glTF", 4), 0);
    EXPECT_EQ(le32(&bytes[4]), 2u);
    EXPECT_EQ(le32(&bytes[8]), bytes.size());
    const std::uint32_t jlen = le32(&bytes[12]);
    EXPECT_EQ(std::memcmp(&bytes[16], "JSON", 4), 0);
    EXPECT_EQ(jlen % 4, 0u);
    a.doc = json::parse(bytes.begin() + 20, bytes.begin() + 20 + jlen);  // spaces pad
    const std::size_t b = 20 + jlen;
    const std::uint32_t blen = le32(&bytes[b]);
    EXPECT_EQ(std::memcmp(&bytes[b + 4], "BIN\0", 4), 0);
    EXPECT_EQ(blen % 4, 0u);
    EXPECT_EQ(b + 8 + blen, bytes.size());
    a.bin.assign(bytes.begin() + b + 8, bytes.end());
  } else {
    a.doc = json::parse(bytes);
    a.bin = slurp(a.dir / a.doc["buffers"][0]["uri"].get<std::string>());
  }
  EXPECT_EQ(a.doc["asset"]["version"], "2.0");
  return a;
}

struct Png {
  std::size_t w = 0, h = 0;
  std::vector<std::uint8_t> rgb;
};

Png decode(const std::vector<std::uint8_t>& bytes) {
  png_image img;
  std::memset(&img, 0, sizeof img);
  img.version = PNG_IMAGE_VERSION;
  EXPECT_TRUE(png_image_begin_read_from_memory(&img, bytes.data(), bytes.size()));
  img.format = PNG_FORMAT_RGB;
  Png p{img.width, img.height, std::vector<std::uint8_t>(PNG_IMAGE_SIZE(img))};
  EXPECT_TRUE(png_image_finish_read(&img, nullptr, p.rgb.data(), 0, nullptr));
  return p;
}

/// GGX widths (wide, narrow) and the wide axis' azimuth mod pi, the way glTF's definition reads
/// roughness r, strength s and the direction angle.
struct Widths {
  double wide, narrow, axis;
};
Widths from_gltf(double r, double s, double angle) {
  const double ar = r * r;
  return {ar * (1 - s * s) + 1 * s * s, ar, angle};
}
/// The same description of a GGX (alpha_x along phi, alpha_y across).
Widths canonical(double ax, double ay, double phi) {
  if (ay > ax) return {ay, ax, phi + M_PI / 2};
  return {ax, ay, phi};
}
/// Difference of two axis directions (mod pi), in [0, pi/2].
double axis_diff(double a, double b) { return std::abs(std::remainder(a - b, M_PI)); }

GltfMaterial ggx_material(double ax, double ay, double phi) {
  BrdfSpec spec;
  spec.kind = BrdfSpec::Kind::Analytic;
  spec.model.model = "ggx";
  spec.model.alpha_x = ax;
  spec.model.alpha_y = ay;
  spec.model.phi = phi;
  return gltf_material(spec, MaterialSpec::named_metal("Al"));
}

struct TempDir {
  fs::path path = fs::temp_directory_path() / ("mb_gltf_" + std::to_string(::getpid()));
  TempDir() { fs::create_directories(path); }
  ~TempDir() { fs::remove_all(path); }
};

}  // namespace

TEST(Gltf, MappingFollowsTheExtensionsDefinition) {
  // Isotropic: strength 0, roughness sqrt(alpha).
  auto g = gltf_anisotropy({0.09, 0.09, 0.3});
  EXPECT_NEAR(g.roughness, 0.3, 1e-15);
  EXPECT_EQ(g.strength, 0.0);
  // alpha_t = r^2 (1 - s^2) + s^2 along the rotation.
  g = gltf_anisotropy({0.3, 0.1, 0.2});
  EXPECT_NEAR(g.roughness * g.roughness, 0.1, 1e-15);
  EXPECT_NEAR(0.1 * (1 - g.strength * g.strength) + g.strength * g.strength, 0.3, 1e-15);
  EXPECT_NEAR(g.rotation, 0.2, 1e-15);
  // The wider axis is the direction: alpha_y wider turns it by 90 deg, folded into (-90, 90].
  g = gltf_anisotropy({0.1, 0.3, 1.0});
  EXPECT_NEAR(g.rotation, 1.0 + M_PI / 2 - M_PI, 1e-12);
  // Widths over 1 are clamped and said.
  bool clamped = false;
  g = gltf_anisotropy({2.0, 0.5, 0}, &clamped);
  EXPECT_TRUE(clamped);
  EXPECT_NEAR(g.strength, 1.0, 1e-15);
  EXPECT_THROW(gltf_anisotropy({0.0, 0.1, 0}), InputError);
}

TEST(Gltf, WidthsAndAzimuthRecoveredFromTheFile) {
  TempDir t;
  const struct {
    double ax, ay, phi;
  } cases[] = {{0.2, 0.2, 0.0},  {0.05, 0.4, 0.0},    {0.3, 0.02, 0.7},
               {0.1, 0.6, -1.2}, {0.011, 0.013, 2.9}, {0.9, 0.25, -0.4}};
  double worst = 0;
  for (const auto& c : cases)
    for (const char* ext : {".glb", ".gltf"}) {
      const fs::path out = t.path / (std::string("m") + ext);
      const GltfMaterial m = ggx_material(c.ax, c.ay, c.phi);
      write_gltf(m, out.string());
      const Asset a = read_asset(out);
      const json& mat = a.doc["materials"][0];
      const json& pbr = mat["pbrMetallicRoughness"];
      EXPECT_EQ(pbr["metallicFactor"], 1.0);
      const double r = pbr["roughnessFactor"];
      double s = 0, rot = 0;
      if (mat.contains("extensions")) {
        s = mat["extensions"]["KHR_materials_anisotropy"]["anisotropyStrength"];
        rot = mat["extensions"]["KHR_materials_anisotropy"]["anisotropyRotation"];
        EXPECT_NE(std::find(a.doc["extensionsUsed"].begin(), a.doc["extensionsUsed"].end(),
                            "KHR_materials_anisotropy"),
                  a.doc["extensionsUsed"].end());
      } else {
        EXPECT_EQ(c.ax, c.ay) << "an anisotropic material without the extension";
      }
      const Widths got = from_gltf(r, s, rot), want = canonical(c.ax, c.ay, c.phi);
      worst = std::max({worst, std::abs(got.wide - want.wide), std::abs(got.narrow - want.narrow)});
      EXPECT_NEAR(got.wide, want.wide, 1e-6) << c.ax << " " << c.ay;
      EXPECT_NEAR(got.narrow, want.narrow, 1e-6);
      if (c.ax != c.ay) {
        worst = std::max(worst, axis_diff(got.axis, want.axis));
        EXPECT_LT(axis_diff(got.axis, want.axis), 1e-6);
      }
      // The library's inverse agrees with the definition.
      const AnisotropicAlpha inv = ggx_from_gltf({r, s, rot});
      EXPECT_NEAR(inv.alpha_x, got.wide, 1e-15);
      EXPECT_NEAR(inv.alpha_y, got.narrow, 1e-15);
    }
  std::printf("worst round-trip error of the GGX widths / azimuth: %.3g\n", worst);
}

TEST(Gltf, MeshesAreWhatGltfRequires) {
  TempDir t;
  const fs::path out = t.path / "m.glb";
  write_gltf(ggx_material(0.1, 0.3, 0.5), out.string());
  const Asset a = read_asset(out);
  ASSERT_EQ(a.doc["meshes"].size(), 2u);
  for (const json& mesh : a.doc["meshes"]) {
    const json& prim = mesh["primitives"][0];
    const auto floats = [&](const char* attr) {
      const json& acc = a.doc["accessors"][prim["attributes"][attr].get<int>()];
      EXPECT_EQ(acc["componentType"], 5126);
      const auto bytes = a.view(acc["bufferView"]);
      std::vector<float> v(bytes.size() / 4);
      std::memcpy(v.data(), bytes.data(), bytes.size());
      return std::pair{v, acc};
    };
    const auto [pos, pacc] = floats("POSITION");
    const auto [nrm, nacc] = floats("NORMAL");
    const auto [tan, tacc] = floats("TANGENT");
    const std::size_t n = pos.size() / 3;
    ASSERT_EQ(nrm.size(), 3 * n);
    ASSERT_EQ(tan.size(), 4 * n);
    for (int k = 0; k < 3; ++k) {  // min/max are the data's own
      float lo = INFINITY, hi = -INFINITY;
      for (std::size_t i = 0; i < n; ++i)
        lo = std::min(lo, pos[3 * i + k]), hi = std::max(hi, pos[3 * i + k]);
      EXPECT_EQ(pacc["min"][k].get<float>(), lo);
      EXPECT_EQ(pacc["max"][k].get<float>(), hi);
    }
    for (std::size_t i = 0; i < n; ++i) {
      const double nn = std::hypot(nrm[3 * i], nrm[3 * i + 1], nrm[3 * i + 2]);
      const double tt = std::hypot(tan[4 * i], tan[4 * i + 1], tan[4 * i + 2]);
      const double nt = nrm[3 * i] * tan[4 * i] + nrm[3 * i + 1] * tan[4 * i + 1] +
                        nrm[3 * i + 2] * tan[4 * i + 2];
      ASSERT_NEAR(nn, 1, 1e-6);
      ASSERT_NEAR(tt, 1, 1e-6);
      ASSERT_NEAR(nt, 0, 1e-6);
      ASSERT_EQ(tan[4 * i + 3], 1.0f);
    }
    // Triangles counter-clockwise seen from outside: the face normal agrees with the vertices'.
    const json& iacc = a.doc["accessors"][prim["indices"].get<int>()];
    const auto ib = a.view(iacc["bufferView"]);
    std::vector<std::uint32_t> idx(ib.size() / 4);
    std::memcpy(idx.data(), ib.data(), ib.size());
    for (std::size_t f = 0; f + 2 < idx.size(); f += 3) {
      const float* p0 = &pos[3 * idx[f]];
      const float* p1 = &pos[3 * idx[f + 1]];
      const float* p2 = &pos[3 * idx[f + 2]];
      const double e1[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
      const double e2[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
      const double c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                           e1[0] * e2[1] - e1[1] * e2[0]};
      const float* nv = &nrm[3 * idx[f]];
      ASSERT_GT(c[0] * nv[0] + c[1] * nv[1] + c[2] * nv[2], 0) << mesh["name"] << " face " << f / 3;
    }
  }
}

TEST(Gltf, TexturePerTexelAnisotropyWithinQuantisation) {
  TempDir t;
  const std::size_t nx = 24, ny = 16;
  ParamTexture tex = ParamTexture::empty(nx, ny, 20e-6, "");
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Widths> want(nx * ny);
  for (std::size_t i = 0; i < nx * ny; ++i) {
    const double ax = 0.004 + 0.5 * u(rng), ay = 0.004 + 0.5 * u(rng), tz = M_PI * (2 * u(rng) - 1);
    tex.channel[0][i] = float(ax);
    tex.channel[1][i] = float(ay);
    tex.channel[2][i] = tex.channel[3][i] = 0;
    tex.channel[4][i] = float(tz);
    tex.valid[i] = 1;
    tex.why_invalid[i].clear();
    // The ellipsoid's theta_z turns its axes by -theta_z (microfacet.hpp).
    want[i] = canonical(tex.channel[0][i], tex.channel[1][i], -double(tex.channel[4][i]));
  }
  const fs::path exr = t.path / "tex.exr";
  write_param_texture(tex, exr.string());
  BrdfSpec spec;
  spec.kind = BrdfSpec::Kind::Texture;
  spec.texture = exr.string();
  const GltfMaterial m = gltf_material(spec, MaterialSpec::named_metal("Fe"));
  ASSERT_EQ(m.texture.size(), 1u);
  for (const char* ext : {".glb", ".gltf"}) {
    const fs::path out = t.path / (std::string("t") + ext);
    GltfExportOptions o;
    o.uv_scale = 3;
    write_gltf(m, out.string(), o);
    const Asset a = read_asset(out);
    const json& mat = a.doc["materials"][0];
    const json& pbr = mat["pbrMetallicRoughness"];
    const json& an = mat["extensions"]["KHR_materials_anisotropy"];
    const double rf = pbr["roughnessFactor"], sf = an["anisotropyStrength"],
                 rot = an["anisotropyRotation"];
    EXPECT_EQ(pbr["metallicRoughnessTexture"]["extensions"]["KHR_texture_transform"]["scale"][0],
              3.0);
    const auto src = [&](const json& info) {
      return a.doc["textures"][info["index"].get<int>()]["source"].get<int>();
    };
    const Png rough = decode(a.image(src(pbr["metallicRoughnessTexture"])));
    const Png aniso = decode(a.image(src(an["anisotropyTexture"])));
    ASSERT_EQ(rough.w, nx);
    ASSERT_EQ(rough.h, ny);
    ASSERT_EQ(aniso.w, nx);
    ASSERT_EQ(aniso.h, ny);
    // One 8-bit step is 1/255 of the factor; rounding is within half of it.
    const double dr = 0.5 / 255 * rf, ds = 0.5 / 255 * sf;
    double worst_narrow = 0, worst_wide = 0, worst_axis = 0;
    for (std::size_t i = 0; i < nx * ny; ++i) {
      const std::uint8_t* pr = &rough.rgb[3 * i];
      const std::uint8_t* pa = &aniso.rgb[3 * i];
      EXPECT_EQ(pr[2], 255) << "metallic";
      const double r = pr[1] / 255.0 * rf, s = pa[2] / 255.0 * sf;
      // The direction: RG in [0, 1] -> XY in [-1, 1], turned by anisotropyRotation.
      const double x = pa[0] / 255.0 * 2 - 1, y = pa[1] / 255.0 * 2 - 1;
      const Widths got = from_gltf(r, s, std::atan2(y, x) + rot);
      const Widths& w = want[i];
      const double rt = std::sqrt(w.narrow), st = std::sqrt((w.wide - w.narrow) / (1 - w.narrow));
      const double tol_narrow = (2 * rt + dr) * dr + 1e-7;
      const double tol_wide =
          2 * rt * (1 - st * st) * dr + 2 * st * (1 - rt * rt) * ds + dr * dr + ds * ds + 1e-7;
      EXPECT_LE(std::abs(got.narrow - w.narrow), tol_narrow) << "texel " << i;
      EXPECT_LE(std::abs(got.wide - w.wide), tol_wide) << "texel " << i;
      // Each of X, Y within 1/255: the angle within asin(sqrt(2)/255 / |XY|).
      EXPECT_LE(axis_diff(got.axis, w.axis), std::asin(std::sqrt(2.0) / 255 / 0.99)) << i;
      worst_narrow = std::max(worst_narrow, std::abs(got.narrow - w.narrow) / tol_narrow);
      worst_wide = std::max(worst_wide, std::abs(got.wide - w.wide) / tol_wide);
      worst_axis = std::max(worst_axis, axis_diff(got.axis, w.axis));
    }
    std::printf("%s: worst error / quantisation bound: narrow %.3f, wide %.3f; axis %.4f rad\n",
                ext, worst_narrow, worst_wide, worst_axis);
  }
}

TEST(Gltf, WarningsSayWhatGltfCannotHold) {
  // Exact conductor Fresnel -> Schlick; a GGX material has no shape warning.
  GltfMaterial m = ggx_material(0.1, 0.2, 0);
  ASSERT_EQ(m.warnings.size(), 1u);
  EXPECT_NE(m.warnings[0].find("Schlick"), std::string::npos);
  for (int i = 0; i < 3; ++i) EXPECT_GT(m.base_color[i], 0.8);  // aluminium
  // Beckmann becomes its GGX fit, with the fit's distance.
  BrdfSpec spec;
  spec.kind = BrdfSpec::Kind::Analytic;
  spec.model.model = "beckmann";
  spec.model.alpha_x = spec.model.alpha_y = 0.2;
  m = gltf_material(spec, MaterialSpec::named_metal("Au"));
  ASSERT_GE(m.warnings.size(), 2u);
  EXPECT_NE(m.warnings[0].find("Hellinger"), std::string::npos);
  EXPECT_NEAR(m.ggx.alpha_x, 0.2, 0.08);
  EXPECT_GT(m.base_color[0], m.base_color[2]);  // gold is yellow
  spec.kind = BrdfSpec::Kind::Lambertian;
  EXPECT_THROW(gltf_material(spec, MaterialSpec{}), InputError);
  EXPECT_THROW(write_gltf(m, "x.obj"), InputError);
}
