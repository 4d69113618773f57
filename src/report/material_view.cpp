// The interactive material view of the predict report (material_view.hpp). The shader evaluates
// f = F D G2 / (4 |wi.n| |wo.n|) with the same formulas as src/models/microfacet.cpp (D, Lambda,
// height-correlated G2 with clamped G1) and fresnel_conductor_siegel (src/models/fresnel.cpp);
// tests/browser/report_test.mjs reads the shader's values back and compares them with
// `microbrdf brdf slice` at the same directions.
#include "report/material_view.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "microbrdf/envmap_image.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/image.hpp"
#include "microbrdf/microfacet.hpp"
#include "report/html.hpp"

namespace microbrdf::report {
namespace {

using nlohmann::json;

constexpr int kEnvW = 128, kEnvH = 64;
// `render --scene sphere`'s pinhole (src/render/scene.cpp, preview_camera): at (0, 0, 4) looking
// at the unit sphere, tan of the half field of view 1.15/4. The view draws the report's sphere
// render with it; the browser test compares the two, background included.
constexpr double kSphereCameraDistance = 4, kSphereTanHalfFov = 1.15 / 4;
// Display wavelengths of the three channels (nm): where the sRGB primaries' colour matching
// peaks lie, roughly; the view is an RGB approximation of the spectral renders above.
constexpr double kRgbNm[3] = {610, 550, 465};

double jnum(const json& v, double fallback) { return v.is_number() ? v.get<double>() : fallback; }

json matrix(const Eigen::Matrix3d& r) {
  json a = json::array();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) a.push_back(r(i, j));
  return a;
}

// The report's environment map, read as the renderer reads it (OpenEXR or Radiance .hdr, the same
// checks), box-filtered to kEnvW x kEnvH (every source pixel lands in exactly one target pixel),
// times `scale`. Orientation as the renderer's: row 0 the zenith, the middle column straight
// ahead (-z).
std::vector<float> read_envmap_box_filtered(const std::string& path, double scale) {
  const EnvmapImage img = read_envmap(path);
  const long w = img.width, h = img.height;
  std::vector<double> sum(std::size_t(kEnvW) * kEnvH * 3, 0.0), count(std::size_t(kEnvW) * kEnvH);
  for (long y = 0; y < h; ++y) {
    const long tr = std::min<long>(kEnvH - 1, y * kEnvH / h);
    for (long x = 0; x < w; ++x) {
      const long tc = std::min<long>(kEnvW - 1, x * kEnvW / w);
      const std::size_t t = std::size_t(tr) * kEnvW + tc;
      for (int k = 0; k < 3; ++k) {
        const float v = img.rgb[(std::size_t(y) * w + x) * 3 + k];
        sum[t * 3 + k] += std::isfinite(v) ? std::max(0.0f, v) : 0.0f;
      }
      count[t] += 1;
    }
  }
  std::vector<float> out(sum.size());
  for (std::size_t t = 0; t < count.size(); ++t)
    for (int k = 0; k < 3; ++k)
      out[t * 3 + k] = float(count[t] > 0 ? scale * sum[t * 3 + k] / count[t] : 0.0);
  return out;
}

// The predict renders' built-in lights when there is no map: a uniform sky of 0.25 and two round
// softboxes (radiance 6 and 4) seen from the origin, painted into the map.
std::vector<float> builtin_sky(double scale) {
  std::vector<float> out(std::size_t(kEnvW) * kEnvH * 3, float(0.25 * scale));
  const struct {
    Eigen::Vector3d pos;
    double radius, radiance;
  } disks[] = {{{-4, 4, 3}, 1.2, 6}, {{4, 3, 2}, 0.8, 4}};
  for (int r = 0; r < kEnvH; ++r)
    for (int c = 0; c < kEnvW; ++c) {
      const double theta = M_PI * (r + 0.5) / kEnvH, phi = 2 * M_PI * ((c + 0.5) / kEnvW - 0.5);
      const Eigen::Vector3d d(std::sin(theta) * std::sin(phi), std::cos(theta),
                              -std::sin(theta) * std::cos(phi));
      for (const auto& k : disks) {
        const double cos_half = std::cos(std::atan(k.radius / k.pos.norm()));
        if (d.dot(k.pos.normalized()) >= cos_half)
          for (int ch = 0; ch < 3; ++ch)
            out[(std::size_t(r) * kEnvW + c) * 3 + ch] = float(k.radiance * scale);
      }
    }
  return out;
}

}  // namespace

std::string colour_gradient(const std::string& direction) {
  std::string g = "linear-gradient(" + direction;
  for (int i = 0; i < kRampAnchors; ++i) {
    std::uint8_t c[3];
    false_colour(double(i) / (kRampAnchors - 1), c);
    char hex[8];
    std::snprintf(hex, sizeof hex, "#%02x%02x%02x", c[0], c[1], c[2]);
    g += ",";
    g += hex;
  }
  return g + ")";
}

json material_view_data(const json& s_in) {
  json s = s_in;  // operator[] on a mutable copy: a missing key reads null
  json data;
  json models = json::array();
  for (auto& f : s["fits"]) {
    const std::string key = f["model"].is_string() ? f["model"].get<std::string>() : "";
    json& q = f["params"];
    const double ax = jnum(q["alpha_x"], 0.1), ay = jnum(q["alpha_y"], 0.1);
    Eigen::Matrix3d r;
    int family = 0;  // 0: ellipsoid form (GGX is the ellipsoid with R = Rz(-phi)), 1: Beckmann
    if (key == "ellipsoid") {
      r = rotation_x(jnum(q["theta_x"], 0)) * rotation_y(jnum(q["theta_y"], 0)) *
          rotation_z(jnum(q["theta_z"], 0));
    } else if (key == "ggx" || key == "beckmann") {
      r = rotation_z(-jnum(f["phi"], 0));
      family = key == "beckmann" ? 1 : 0;
    } else {
      continue;
    }
    models.push_back({{"key", key},
                      {"family", family},
                      {"alpha", {ax, ay}},
                      {"R", matrix(r)},
                      {"theta_x", jnum(q["theta_x"], 0)},
                      {"theta_y", jnum(q["theta_y"], 0)},
                      {"theta_z", jnum(q["theta_z"], 0)},
                      {"phi", jnum(f["phi"], 0)}});
  }
  data["models"] = models;

  // Optical constants at the display wavelengths: the built-in metal by name, else the summary's
  // n, k at 555 nm for all three channels (a grey approximation, said in the caption).
  json& m = s["material"];
  json eta = json::array(), kappa = json::array();
  std::string fresnel_note;
  try {
    const std::string name = s["settings"]["metal"].is_string()
                                 ? s["settings"]["metal"].get<std::string>()
                                 : std::string();
    const OpticalConstants c = metal(name);
    for (double nm : kRgbNm) {
      eta.push_back(c.n(nm * 1e-9));
      kappa.push_back(c.k(nm * 1e-9));
    }
    fresnel_note = "exact conductor Fresnel of " + c.name + " at 610, 550 and 465 nm (R, G, B)";
  } catch (const std::exception&) {
    eta = json::array({jnum(m["n_555nm"], 1), jnum(m["n_555nm"], 1), jnum(m["n_555nm"], 1)});
    kappa = json::array({jnum(m["k_555nm"], 0), jnum(m["k_555nm"], 0), jnum(m["k_555nm"], 0)});
    fresnel_note = "exact conductor Fresnel with n, k at 555 nm in all three channels (grey)";
  }
  data["eta"] = eta;
  data["kappa"] = kappa;
  data["fresnel"] = fresnel_note;

  // The environment: the report's map (scaled as the renders scale it), else the built-in lights.
  const double scale = jnum(s["settings"]["envmap_scale"], 1.0);
  std::vector<float> env;
  std::string env_note;
  const json& path = s["settings"]["envmap"];
  if (path.is_string() && std::filesystem::is_regular_file(path.get<std::string>())) {
    try {
      env = read_envmap_box_filtered(path.get<std::string>(), scale);
      env_note = "the environment map " +
                 std::filesystem::path(path.get<std::string>()).filename().string() +
                 ", box-filtered to 128 x 64";
    } catch (const std::exception&) {
      env.clear();
    }
  }
  if (env.empty()) {
    env = builtin_sky(scale);
    env_note =
        path.is_string() && path.get<std::string>().rfind("none", 0) != 0
            ? "a dim sky and two lights (the map " + path.get<std::string>() + " could not be read)"
            : "the renders' built-in lights: a dim sky and two round softboxes";
  }
  auto env_json = [](const std::vector<float>& e, const std::string& name) {
    std::vector<std::uint8_t> bytes(e.size() * 4);
    std::memcpy(bytes.data(), e.data(), bytes.size());  // little-endian float32, as JS reads it
    return json{
        {"name", name}, {"width", kEnvW}, {"height", kEnvH}, {"rgb_f32_base64", base64(bytes)}};
  };
  json envs = json::array({env_json(env, "the renders' lighting")});
  // A neutral studio map beside the report's one (the bundled maps sit in one folder): under a
  // warm courtyard a grey metal looks bronze; the studio shows the material's own colour.
  if (path.is_string() && std::filesystem::is_regular_file(path.get<std::string>())) {
    const auto studio =
        std::filesystem::path(path.get<std::string>()).parent_path() / "blender_studio.exr";
    if (std::filesystem::path(path.get<std::string>()).filename() != "blender_studio.exr" &&
        std::filesystem::is_regular_file(studio)) {
      try {
        envs.push_back(env_json(read_envmap_box_filtered(studio.string(), 1.0), "neutral studio"));
        env_note += "; or the neutral studio map blender_studio.exr beside it";
      } catch (const std::exception&) {
      }
    }
  }
  data["envs"] = envs;
  json ramp = json::array();
  for (int i = 0; i < kRampAnchors; ++i) {
    std::uint8_t c[3];
    false_colour(double(i) / (kRampAnchors - 1), c);
    ramp.push_back({c[0], c[1], c[2]});
  }
  data["ramp"] = ramp;
  data["env_note"] = env_note;
  data["camera"] = {{"distance", kSphereCameraDistance}, {"tan_half_fov", kSphereTanHalfFov}};
  // The exposure of the report's sphere render (its automatic one), so that the view shows the
  // sphere as that image does; 0 without one.
  double stops = 0;
  if (s["renders"].is_array())
    for (const auto& r : s["renders"])
      if (r.contains("scene") && r["scene"] == "sphere") stops = jnum(r["exposure_stops"], 0);
  data["exposure_stops"] = stops;
  return data;
}

namespace {

const char* kShader = R"GLSL(#version 300 es
precision highp float;
precision highp int;
uniform int uMode;           // 0: the sphere; 1: one BRDF value (uProbeWi, uProbeWo); 2: lobe
uniform int uFamily;         // 0: ellipsoid form (ellipsoid, GGX); 1: Beckmann
uniform mat3 uR;             // rotation of the ellipsoid convention (Beckmann/GGX: Rz(-phi))
uniform vec2 uAlpha;
uniform vec3 uEta, uKappa;   // per channel
uniform vec3 uProbeWi, uProbeWo;
uniform sampler2D uEnv;
uniform float uEnvRot, uExposure, uSampleRot;
uniform vec2 uSize;
uniform vec2 uCamera;        // tan of the half field of view, distance from the origin
uniform vec2 uEnvSize;       // the map's width and height (texels)
uniform vec2 uSeq[64];
uniform int uCount;
out vec4 outColor;
const float PI = 3.14159265358979;

// fresnel_conductor_siegel, per channel
vec3 fresnel(float cosi, vec3 eta, vec3 kappa) {
  float c = min(abs(cosi), 1.0), c2 = c * c, s2 = max(0.0, 1.0 - c2);
  vec3 t = eta * eta - kappa * kappa - s2;
  vec3 a2b2 = sqrt(t * t + 4.0 * eta * eta * kappa * kappa);
  vec3 a = sqrt(max(vec3(0.0), 0.5 * (a2b2 + t)));
  vec3 rs = (a2b2 - 2.0 * a * c + c2) / (a2b2 + 2.0 * a * c + c2);
  vec3 rp = rs * (a2b2 * c2 - 2.0 * a * c * s2 + s2 * s2) / (a2b2 * c2 + 2.0 * a * c * s2 + s2 * s2);
  return 0.5 * (rs + rp);
}
// erfc for x >= 0 (Abramowitz & Stegun 7.1.26, |error| < 1.5e-7), odd extension below 0
float erfc_(float x) {
  float z = abs(x), t = 1.0 / (1.0 + 0.3275911 * z);
  float y = t * (0.254829592 + t * (-0.284496736 + t * (1.421413741 + t * (-1.453152027 +
            t * 1.061405429)))) * exp(-z * z);
  return x >= 0.0 ? y : 2.0 - y;
}
float D(vec3 m) {
  if (m.z <= 0.0) return 0.0;
  vec3 l = uR * m;
  if (uFamily == 1) {
    float z2 = l.z * l.z;
    float e = (l.x * l.x / (uAlpha.x * uAlpha.x) + l.y * l.y / (uAlpha.y * uAlpha.y)) / z2;
    return exp(-e) / (PI * uAlpha.x * uAlpha.y * z2 * z2);
  }
  vec3 an = vec3(uAlpha, 1.0) * uR[2];         // A n = S R n
  vec3 w = l / vec3(uAlpha, 1.0);                // A^-T m = S^-1 R m
  float q = dot(w, w);
  return 1.0 / (PI * uAlpha.x * uAlpha.y * length(an) * q * q);
}
float lambda_(vec3 v) {
  vec3 l = uR * v;
  if (uFamily == 1) {
    float t2 = uAlpha.x * uAlpha.x * l.x * l.x + uAlpha.y * uAlpha.y * l.y * l.y;
    if (t2 <= 0.0) return 0.0;
    float a = l.z / sqrt(t2);
    return -0.5 * erfc_(a) + exp(-a * a) / (2.0 * a * sqrt(PI));
  }
  vec3 an = vec3(uAlpha, 1.0) * uR[2];
  vec3 av = vec3(uAlpha, 1.0) * l;
  float nn = length(an);
  float sigma = length(av) / (2.0 * nn) + dot(av, an) / (2.0 * nn * nn);
  return sigma / v.z - 1.0;
}
float G1(vec3 v) { return v.z <= 0.0 ? 0.0 : min(1.0, 1.0 / (1.0 + lambda_(v))); }
float G2(vec3 wi, vec3 wo, vec3 m) {
  if (dot(wi, m) * wi.z <= 0.0 || dot(wo, m) * wo.z <= 0.0 || wi.z <= 0.0 || wo.z <= 0.0)
    return 0.0;
  float gi = G1(wi), go = G1(wo);
  return 1.0 / (1.0 / gi + 1.0 / go - 1.0);
}
vec3 brdf(vec3 wi, vec3 wo, vec3 eta, vec3 kappa) {
  if (wi.z <= 0.0 || wo.z <= 0.0) return vec3(0.0);
  vec3 hs = wi + wo;
  if (dot(hs, hs) == 0.0) return vec3(0.0);
  vec3 h = normalize(hs);
  float g = G2(wi, wo, h);
  if (g == 0.0) return vec3(0.0);
  return fresnel(dot(wi, h), eta, kappa) * D(h) * g / (4.0 * wi.z * wo.z);
}
// Environment lookup in the renderer's convention (src/render/envmap.hpp): y up, u = 1/2 +
// atan2(x, -z) / 2 pi + rotation / 2 pi, v = theta / pi, row 0 the zenith.
// lod: the mip level (0: the map itself).
vec3 env(vec3 d, float lod) {
  float theta = acos(clamp(d.y, -1.0, 1.0));
  float u = 0.5 + atan(d.x, -d.z) / (2.0 * PI) + uEnvRot / (2.0 * PI);
  return textureLod(uEnv, vec2(fract(u), theta / PI), lod).rgb;
}
vec3 tonemap(vec3 c) {
  c = clamp(c * uExposure, 0.0, 1.0);
  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}
void main() {
  if (uMode == 1) {
    outColor = vec4(brdf(uProbeWi, uProbeWo, uEta, uKappa), 1.0);
    return;
  }
  if (uMode == 2) {  // the BRDF over the outgoing hemisphere (orthographic disk, n up)
    vec2 d = (gl_FragCoord.xy / uSize) * 2.0 - 1.0;
    float dd = dot(d, d);
    outColor = dd >= 1.0 ? vec4(-1.0)
                         : vec4(brdf(uProbeWi, vec3(d, sqrt(1.0 - dd)), uEta, uKappa), 1.0);
    return;
  }
  // `microbrdf render --scene sphere`'s pinhole (src/render/scene.cpp): at (0, 0, uCamera.y),
  // looking along -z, tan of the half field of view uCamera.x; the unit sphere at the origin.
  vec2 p = (gl_FragCoord.xy / uSize) * 2.0 - 1.0;
  vec3 dir = normalize(vec3(p * uCamera.x, -1.0));
  float od = uCamera.y * dir.z, disc = od * od - (uCamera.y * uCamera.y - 1.0);  // o = (0, 0, d)
  if (disc < 0.0) {
    outColor = vec4(tonemap(env(dir, 0.0)), 1.0);
    return;
  }
  vec3 n = vec3(0.0, 0.0, uCamera.y) + (-od - sqrt(disc)) * dir;  // the nearer hit
  // The renders' "linear" brushing: the camera's right (+x) projected into the tangent plane,
  // then turned about n by the brushing slider.
  vec3 t = vec3(1.0, 0.0, 0.0) - n.x * n;
  t = dot(t, t) > 1e-12 ? normalize(t) : vec3(0.0, 1.0, 0.0);
  t = cos(uSampleRot) * t + sin(uSampleRot) * cross(n, t);
  vec3 b = cross(n, t);
  vec3 woW = -dir;
  vec3 wo = vec3(dot(woW, t), dot(woW, b), dot(woW, n));
  mat3 rt = transpose(uR);
  vec3 sum = vec3(0.0);
  // D-proportional proposal: anisotropic GGX normals (density D_ggx(m') m'.z) in the model's own
  // frame, turned by R^T; the estimate f cos L / pdf is exact in expectation for every model.
  // Filtered importance sampling (Krivanek & Colbert 2008): each direction reads the map's mip
  // level whose texel covers the solid angle 1 / (N pdf) the direction stands for, so that the
  // fixed directions integrate the whole lobe instead of point-sampling it (half a level more,
  // as three.js' PMREM filtering does, against the fixed directions' aliasing).
  float texel = 2.0 * PI * PI / (uEnvSize.x * uEnvSize.y);  // solid angle of a texel at the equator
  for (int i = 0; i < 64; ++i) {
    if (i >= uCount) break;
    vec2 u = uSeq[i];
    float rr = sqrt(u.x / (1.0 - u.x)), ph = 2.0 * PI * u.y;
    vec3 ml = normalize(vec3(uAlpha.x * rr * cos(ph), uAlpha.y * rr * sin(ph), 1.0));
    float qq = ml.x * ml.x / (uAlpha.x * uAlpha.x) + ml.y * ml.y / (uAlpha.y * uAlpha.y) +
               ml.z * ml.z;
    float pdfm = ml.z / (PI * uAlpha.x * uAlpha.y * qq * qq);
    vec3 m = rt * ml;
    float om = dot(wo, m);
    if (om <= 0.0 || m.z <= 0.0) continue;
    vec3 wi = 2.0 * om * m - wo;
    if (wi.z <= 0.0) continue;
    float pdfi = pdfm / (4.0 * om);
    vec3 wiW = wi.x * t + wi.y * b + wi.z * n;
    float sinTheta = max(sqrt(max(0.0, 1.0 - wiW.y * wiW.y)), 1e-3);
    float lod = max(0.0, 0.5 * log2(1.0 / (float(uCount) * pdfi * texel * sinTheta)) + 0.5);
    sum += brdf(wi, wo, uEta, uKappa) * wi.z * env(wiW, lod) / pdfi;
  }
  outColor = vec4(tonemap(sum / float(uCount)), 1.0);
}
)GLSL";

const char* kScript = R"JS(
(function () {
  "use strict";
  var note = document.getElementById("mbv-status");
  function say(t) { note.textContent = t; }
  var data = JSON.parse(document.getElementById("mbv-data").textContent);
  var canvas = document.getElementById("mbv-canvas");
  var gl = canvas.getContext("webgl2", {preserveDrawingBuffer: true, antialias: false});
  if (!gl || data.models.length === 0) {
    say(!gl ? "This browser offers no WebGL 2: the static renders above show the material."
            : "No fitted model in this report.");
    return;
  }
  var vsrc = "#version 300 es\nvoid main(){vec2 p=vec2(float((gl_VertexID<<1)&2),float(gl_VertexID&2));" +
             "gl_Position=vec4(p*2.0-1.0,0.0,1.0);}";
  function compile(type, src) {
    var sh = gl.createShader(type);
    gl.shaderSource(sh, src);
    gl.compileShader(sh);
    if (!gl.getShaderParameter(sh, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(sh));
    return sh;
  }
  var prog = gl.createProgram();
  gl.attachShader(prog, compile(gl.VERTEX_SHADER, vsrc));
  gl.attachShader(prog, compile(gl.FRAGMENT_SHADER, document.getElementById("mbv-shader").textContent));
  gl.linkProgram(prog);
  if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(prog));
  gl.useProgram(prog);
  var U = {};
  ["uMode", "uFamily", "uR", "uAlpha", "uEta", "uKappa", "uProbeWi", "uProbeWo", "uEnv", "uEnvRot",
   "uExposure", "uSampleRot", "uSize", "uCamera", "uEnvSize", "uSeq", "uCount"].forEach(function (k) {
    U[k] = gl.getUniformLocation(prog, k);
  });
  // Environment textures: float32 RGB from the page, stored as RGBA16F (filterable in WebGL 2),
  // with every mip level down to 1 x 1 made here by 2 x 2 box averages (the mean radiance of each
  // level is the map's; the filtered importance sampling of the shader reads them).
  var envTex = data.envs.map(function (env) {
    var bin = atob(env.rgb_f32_base64), bytes = new Uint8Array(bin.length);
    for (var i = 0; i < bin.length; ++i) bytes[i] = bin.charCodeAt(i);
    var rgb = new Float32Array(bytes.buffer), w = env.width, h = env.height;
    var level = new Float32Array(w * h * 4);
    for (var j = 0; j < w * h; ++j) {
      level[4 * j] = rgb[3 * j]; level[4 * j + 1] = rgb[3 * j + 1]; level[4 * j + 2] = rgb[3 * j + 2];
      level[4 * j + 3] = 1;
    }
    var tex = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, tex);
    for (var lv = 0; ; ++lv) {
      gl.texImage2D(gl.TEXTURE_2D, lv, gl.RGBA16F, w, h, 0, gl.RGBA, gl.FLOAT, level);
      if (w === 1 && h === 1) break;
      var w2 = Math.max(1, w >> 1), h2 = Math.max(1, h >> 1), next = new Float32Array(w2 * h2 * 4);
      for (var y = 0; y < h2; ++y)
        for (var x = 0; x < w2; ++x)
          for (var k = 0; k < 4; ++k) {
            var acc = 0, cnt = 0;
            for (var dy = 0; dy < (h > 1 ? 2 : 1); ++dy)
              for (var dx = 0; dx < (w > 1 ? 2 : 1); ++dx) {
                acc += level[(((h > 1 ? 2 * y : y) + dy) * w + (w > 1 ? 2 * x : x) + dx) * 4 + k];
                cnt++;
              }
            next[(y * w2 + x) * 4 + k] = acc / cnt;
          }
      level = next; w = w2; h = h2;
    }
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.LINEAR_MIPMAP_LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.REPEAT);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
    return tex;
  });
  gl.uniform1i(U.uEnv, 0);
  // 64 Hammersley points, the same for every pixel (no noise; a fixed quadrature).
  var seq = new Float32Array(128);
  for (var s = 0; s < 64; ++s) {
    var bits = s, inv = 0, f = 0.5;
    while (bits) { if (bits & 1) inv += f; bits >>= 1; f *= 0.5; }
    seq[2 * s] = (s + 0.5) / 64; seq[2 * s + 1] = inv;
  }
  gl.uniform2fv(U.uSeq, seq);
  gl.uniform1i(U.uCount, 64);
  var byKey = {};
  data.models.forEach(function (m) { byKey[m.key] = m; });
  // The exposure starts at the report's sphere render's (its slider's value).
  var state = {model: data.models[0].key, env: 0, envRot: 0, sampleRot: 0, lobeTheta: 30, lobePhi: 180,
               exposure: Math.pow(2, data.exposure_stops)};
  function setModel(m, eta, kappa) {
    gl.uniform1i(U.uFamily, m.family);
    gl.uniformMatrix3fv(U.uR, true, new Float32Array(m.R));
    gl.uniform2f(U.uAlpha, m.alpha[0], m.alpha[1]);
    gl.uniform3fv(U.uEta, eta);
    gl.uniform3fv(U.uKappa, kappa);
  }
  function draw() {
    gl.bindFramebuffer(gl.FRAMEBUFFER, NONE);
    gl.viewport(0, 0, canvas.width, canvas.height);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, envTex[state.env]);
    setModel(byKey[state.model], data.eta, data.kappa);
    gl.uniform1i(U.uMode, 0);
    gl.uniform1f(U.uEnvRot, state.envRot * Math.PI / 180);
    gl.uniform1f(U.uExposure, state.exposure);
    gl.uniform1f(U.uSampleRot, state.sampleRot * Math.PI / 180);
    gl.uniform2f(U.uSize, canvas.width, canvas.height);
    gl.uniform2f(U.uCamera, data.camera.tan_half_fov, data.camera.distance);
    gl.uniform2f(U.uEnvSize, data.envs[state.env].width, data.envs[state.env].height);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    var m = byKey[state.model];
    say(m.key + ": alpha_x " + m.alpha[0].toPrecision(4) + ", alpha_y " + m.alpha[1].toPrecision(4) +
        "; " + data.envs[state.env].name + " turned " + state.envRot + " deg, brushing turned " + state.sampleRot +
        " deg, exposure x" + state.exposure.toPrecision(3) + ".");
  }
  // One BRDF value (1/sr) as the shader computes it, for the tests: directions in the surface
  // frame (n = +z, both pointing away), one constant n, k in every channel; false without
  // float render targets. (NONE: the default framebuffer; the page avoids the word for "no
  // object", which the report's checks read as a missing number.)
  var NONE = void 0, probeFb = NONE, lobeFb = NONE, LOBE = 160;
  var floatOk = !!gl.getExtension("EXT_color_buffer_float");
  function floatTarget(size) {
    var t = gl.createTexture();
    gl.activeTexture(gl.TEXTURE1);
    gl.bindTexture(gl.TEXTURE_2D, t);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, size, size, 0, gl.RGBA, gl.FLOAT,
                  new Float32Array(size * size * 4));
    gl.activeTexture(gl.TEXTURE0);
    var fb = gl.createFramebuffer();
    gl.bindFramebuffer(gl.FRAMEBUFFER, fb);
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, t, 0);
    return fb;
  }
  function probe(key, wi, wo, n, k) {
    if (!floatOk) return false;
    if (!probeFb) probeFb = floatTarget(1);
    gl.bindFramebuffer(gl.FRAMEBUFFER, probeFb);
    gl.viewport(0, 0, 1, 1);
    setModel(byKey[key], [n, n, n], [k, k, k]);
    gl.uniform1i(U.uMode, 1);
    gl.uniform3fv(U.uProbeWi, wi);
    gl.uniform3fv(U.uProbeWo, wo);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    var out = new Float32Array(4);
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.FLOAT, out);
    gl.bindFramebuffer(gl.FRAMEBUFFER, NONE);
    return out[1];
  }
  // The lobe: f(wi, wo) at 550 nm over the outgoing hemisphere, read back as floats, drawn with
  // a log colour scale (4 decades below the largest value); the values show on hover.
  var lobe = {vals: NONE, max: 0, lo: 0, hi: 0};
  var lobeCanvas = document.getElementById("mbv-lobe");
  // The report's false-colour scale (the same anchors as its images), piecewise linear.
  var ramp = data.ramp, nr = ramp.length - 1;
  function colour(t) {
    var x = Math.min(0.999999, Math.max(0, t)) * nr, i = Math.floor(x), f = x - i;
    return ramp[i].map(function (c, j) { return Math.round(c + f * (ramp[i + 1][j] - c)); });
  }
  function lightDir() {
    var t = state.lobeTheta * Math.PI / 180, p = state.lobePhi * Math.PI / 180;
    return [Math.sin(t) * Math.cos(p), Math.sin(t) * Math.sin(p), Math.cos(t)];
  }
  function drawLobe() {
    if (!floatOk) {
      document.getElementById("mbv-lobe-status").textContent =
          "This browser cannot read float pixels back: no lobe view.";
      return;
    }
    if (!lobeFb) lobeFb = floatTarget(LOBE);
    gl.bindFramebuffer(gl.FRAMEBUFFER, lobeFb);
    gl.viewport(0, 0, LOBE, LOBE);
    setModel(byKey[state.model], data.eta, data.kappa);
    gl.uniform1i(U.uMode, 2);
    gl.uniform2f(U.uSize, LOBE, LOBE);
    var wi = lightDir();
    gl.uniform3fv(U.uProbeWi, wi);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    var v = new Float32Array(LOBE * LOBE * 4);
    gl.readPixels(0, 0, LOBE, LOBE, gl.RGBA, gl.FLOAT, v);
    gl.bindFramebuffer(gl.FRAMEBUFFER, NONE);
    var mx = 0;
    for (var i = 1; i < v.length; i += 4) mx = Math.max(mx, v[i]);
    lobe.vals = v; lobe.max = mx;
    lobe.hi = mx > 0 ? Math.log10(mx) : 0; lobe.lo = lobe.hi - 4;
    var g = lobeCanvas.getContext("2d"), img = g.createImageData(LOBE, LOBE);
    for (var r = 0; r < LOBE; ++r)
      for (var c = 0; c < LOBE; ++c) {
        var val = v[((LOBE - 1 - r) * LOBE + c) * 4 + 1], o = (r * LOBE + c) * 4;
        var rgb = val < 0 ? [255, 255, 255]
                          : colour((Math.log10(Math.max(val, 1e-30)) - lobe.lo) / (lobe.hi - lobe.lo));
        img.data[o] = rgb[0]; img.data[o + 1] = rgb[1]; img.data[o + 2] = rgb[2]; img.data[o + 3] = 255;
      }
    g.putImageData(img, 0, 0);
    // The mirror direction (-wi.x, -wi.y): a white ring.
    g.strokeStyle = "#fff";
    g.beginPath();
    g.arc((1 - wi[0]) * LOBE / 2, (1 + wi[1]) * LOBE / 2, 4, 0, 2 * Math.PI);
    g.stroke();
    document.getElementById("mbv-bar-lo").textContent = Math.pow(10, lobe.lo).toPrecision(3) + " 1/sr";
    document.getElementById("mbv-bar-hi").textContent = Math.pow(10, lobe.hi).toPrecision(3) + " 1/sr";
    document.getElementById("mbv-lobe-status").textContent =
        "light at theta_i " + state.lobeTheta + " deg, azimuth " + state.lobePhi +
        " deg; largest value " + mx.toPrecision(4) + " 1/sr. Point at the disk to read a value.";
  }
  lobeCanvas.addEventListener("mousemove", function (e) {
    if (!lobe.vals) return;
    var b = lobeCanvas.getBoundingClientRect();
    var c = Math.floor((e.clientX - b.left) / b.width * LOBE);
    var row = LOBE - 1 - Math.floor((e.clientY - b.top) / b.height * LOBE);
    if (c < 0 || c >= LOBE || row < 0 || row >= LOBE) return;
    var val = lobe.vals[(row * LOBE + c) * 4 + 1];
    var x = (c + 0.5) / LOBE * 2 - 1, y = (row + 0.5) / LOBE * 2 - 1;
    if (val < 0) return;
    document.getElementById("mbv-lobe-status").textContent =
        "f = " + val.toPrecision(4) + " 1/sr at theta_o " +
        (Math.asin(Math.min(1, Math.hypot(x, y))) * 180 / Math.PI).toFixed(1) + " deg, azimuth " +
        (Math.atan2(y, x) * 180 / Math.PI).toFixed(1) + " deg (light at theta_i " +
        state.lobeTheta + " deg, azimuth " + state.lobePhi + " deg).";
  });
  function update() { draw(); drawLobe(); }
  document.querySelectorAll("input[name=mbv-model]").forEach(function (r) {
    r.addEventListener("change", function () { state.model = r.value; update(); });
  });
  document.querySelectorAll("input[name=mbv-envmap]").forEach(function (r) {
    r.addEventListener("change", function () { state.env = Number(r.value); draw(); });
  });
  [["mbv-theta", "lobeTheta"], ["mbv-phi", "lobePhi"]].forEach(function (p) {
    var el = document.getElementById(p[0]);
    el.addEventListener("input", function () { state[p[1]] = Number(el.value); drawLobe(); });
  });
  [["mbv-env", "envRot"], ["mbv-sample", "sampleRot"]].forEach(function (p) {
    var el = document.getElementById(p[0]);
    el.addEventListener("input", function () { state[p[1]] = Number(el.value); draw(); });
  });
  var ex = document.getElementById("mbv-exposure");
  ex.addEventListener("input", function () { state.exposure = Math.pow(2, Number(ex.value)); draw(); });
  window.microbrdfView = {
    models: data.models.map(function (m) { return m.key; }),
    setModel: function (k) {
      state.model = k;
      var r = document.querySelector("input[name=mbv-model][value=" + k + "]");
      if (r) r.checked = true;
      update();
    },
    lobeMax: function () { return lobe.max; },
    environments: data.envs.length,
    setEnvironment: function (i) {
      state.env = i;
      var r = document.querySelector("input[name=mbv-envmap][value='" + i + "']");
      if (r) r.checked = true;
      draw();
    },
    draw: draw,
    probe: probe,
    // For the tests: the exposure (stops; the slider follows), and the canvas size in pixels (no
    // argument: back to 384 x 384).
    exposureStops: data.exposure_stops,
    setExposure: function (stops) { ex.value = String(stops); state.exposure = Math.pow(2, stops); draw(); },
    setSize: function (w, h) { canvas.width = w || 384; canvas.height = h || 384; draw(); }
  };
  update();
})();
)JS";

}  // namespace

std::string material_view_html(const json& summary, const std::string& beside,
                               const std::string& after) {
  const json data = material_view_data(summary);
  const double ev = data["exposure_stops"].get<double>();
  std::string radios;
  bool first = true;
  for (const auto& m : data["models"]) {
    const std::string k = m["key"].get<std::string>();
    radios += "<label><input type=\"radio\" name=\"mbv-model\" value=\"" + escape(k) + "\"" +
              (first ? " checked" : "") + "> " + escape(k) + "</label> ";
    first = false;
  }
  std::string env_radios;
  if (data["envs"].size() > 1) {
    env_radios = "<div><b>environment</b> ";
    for (std::size_t i = 0; i < data["envs"].size(); ++i)
      env_radios += "<label><input type=\"radio\" name=\"mbv-envmap\" value=\"" +
                    std::to_string(i) + "\"" + (i == 0 ? " checked" : "") + "> " +
                    escape(data["envs"][i]["name"].get<std::string>()) + "</label> ";
    env_radios += "</div>\n";
  }
  std::string h;
  h += "<h3 id=\"view\">Interactive view: the fitted models on a sphere</h3>\n";
  h += "<div class=\"mbv\"><canvas id=\"mbv-canvas\" width=\"384\" height=\"384\" "
       "aria-label=\"sphere with the fitted material\"></canvas>\n" +
       beside +
       "<div class=\"mbv-controls\">"
       "<div><b>model</b> " +
       radios + "</div>\n" + env_radios +
       "<div><label>environment rotation <input id=\"mbv-env\" type=\"range\" "
       "min=\"-180\" max=\"180\" step=\"5\" value=\"0\"> (deg)</label></div>\n<div><label>"
       "brushing direction <input id=\"mbv-sample\" type=\"range\" min=\"0\" max=\"180\" "
       "step=\"5\" value=\"0\"> (deg from horizontal)</label></div>\n<div><label>exposure "
       "<input id=\"mbv-exposure\" type=\"range\" min=\"" +
       num(ev - 4) + "\" max=\"" + num(ev + 4) + "\" step=\"0.25\" value=\"" + num(ev) +
       "\"> (stops)</label></div>\n<p id=\"mbv-status\" class=\"cap\">"
       "<noscript>The interactive view needs JavaScript; the static renders above show the "
       "material.</noscript></p></div></div>\n";
  h += "<p class=\"cap\">Drawn in this browser by WebGL 2 (no library, nothing fetched): the "
       "microbrdf BRDF f = F D G2 / (4 |wi.n| |wo.n|) of each fitted NDF (the same formulas as "
       "the C++ models, checked against <code>microbrdf brdf slice</code> by the test suite), "
       "with " +
       escape(data["fresnel"].get<std::string>()) + ", under " +
       escape(data["env_note"].get<std::string>()) +
       "; the camera, the brushing (along the camera's horizontal at 0 deg) and, at first, "
       "the exposure of the sphere render above. Each pixel integrates the map with 64 fixed "
       "directions drawn from the lobe, each reading the map filtered to the solid angle it "
       "stands for (a smooth quadrature, not the path tracer: no interreflection, RGB instead "
       "of spectral; its mean luminance is within 10 % of the path tracer's, checked by the "
       "test suite), tone mapping clamp and sRGB.</p>\n";
  h += after;
  h += "<h3 id=\"lobe\">Interactive view: the BRDF lobe of the chosen model</h3>\n<div "
       "class=\"mbv\">"
       "<canvas id=\"mbv-lobe\" width=\"160\" height=\"160\" aria-label=\"BRDF over the "
       "outgoing hemisphere\"></canvas>\n<div class=\"mbv-bar\"><span id=\"mbv-bar-hi\"></span>"
       "<div class=\"mbv-ramp\" style=\"background:" +
       colour_gradient("to top") +
       "\"></div><span id=\"mbv-bar-lo\"></span></div>\n"
       "<div class=\"mbv-controls\"><div><label>light theta_i <input id=\"mbv-theta\" "
       "type=\"range\" min=\"0\" max=\"85\" step=\"1\" value=\"30\"> (deg)</label></div>\n"
       "<div><label>light azimuth <input id=\"mbv-phi\" type=\"range\" min=\"0\" max=\"360\" "
       "step=\"5\" value=\"180\"> (deg from x)</label></div>\n<p id=\"mbv-lobe-status\" "
       "class=\"cap\"></p><p class=\"cap\">The microfacet BRDF of the model chosen above at "
       "550 nm over the outgoing hemisphere, seen from above (orthographic disk: the surface's x "
       "axis to the right, y up, the rim at 90 deg), log colour over the 4 decades below the "
       "largest value; the white ring marks the mirror direction. Values are the shader's own, "
       "read back as 32-bit floats.</p></div></div>\n";
  std::string js = data.dump();  // "</" would end the script element early
  for (std::size_t i = js.find("</"); i != std::string::npos; i = js.find("</", i + 3))
    js.replace(i, 2, "<\\/");
  h += "<script type=\"application/json\" id=\"mbv-data\">" + js + "</script>\n";
  h += "<script type=\"x-shader/x-fragment\" id=\"mbv-shader\">" + std::string(kShader) +
       "</script>\n";
  h += "<script>" + std::string(kScript) + "</script>\n";
  return h;
}

}  // namespace microbrdf::report
