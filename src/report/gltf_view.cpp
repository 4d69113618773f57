// The glTF view of the predict report (gltf_view.hpp). The environment is the one the project's
// view uses (material_view_data: the report's map box-filtered to 128 x 64, in the renderer's
// orientation), handed to three.js' PMREMGenerator after turning it into three.js' equirectangular
// convention; the camera is the project's view's (the pinhole of the report's sphere render), and
// the exposure slider of that view drives both. tests/browser/report_test.mjs checks that it draws
// and compares it with `microbrdf render` of the same material.
#include "report/gltf_view.hpp"

#include <filesystem>
#include <fstream>
#include <iterator>

#include "report/html.hpp"
#include "report/report_js.hpp"

namespace microbrdf::report {
namespace {

using nlohmann::json;

const char* kModuleScript = R"JS(
const status = document.getElementById("mbg-status");
const say = (t) => { status.textContent = t; };
try {
  const data = JSON.parse(document.getElementById("mbg-data").textContent);
  // Each module becomes a blob: URL; its imports of the other modules are rewritten to their
  // URLs (an inline page has no base URL the specifiers could resolve against).
  const urls = {};
  const specifiers = {"./three.core.js": "core", "three": "three",
                      "../utils/BufferGeometryUtils.js": "buffer_utils",
                      "../utils/SkeletonUtils.js": "skeleton_utils"};
  for (const name of ["core", "three", "buffer_utils", "skeleton_utils", "loader"]) {
    let text = document.getElementById("mbg-mod-" + name).textContent;
    text = text.replace(/from '([^']+)'/g, (all, spec) =>
      specifiers[spec] && urls[specifiers[spec]] ? "from '" + urls[specifiers[spec]] + "'" : all);
    urls[name] = URL.createObjectURL(new Blob([text], {type: "text/javascript"}));
  }
  const THREE = await import(urls.three);
  const {GLTFLoader} = await import(urls.loader);
  const viewData = JSON.parse(document.getElementById("mbv-data").textContent);
  const canvas = document.getElementById("mbg-canvas");
  const renderer = new THREE.WebGLRenderer({canvas, antialias: false, preserveDrawingBuffer: true});
  renderer.setPixelRatio(1);
  renderer.outputColorSpace = THREE.SRGBColorSpace;
  // exposure x colour, clamped, then sRGB: the project's view's tone mapping.
  renderer.toneMapping = THREE.LinearToneMapping;
  const pmrem = new THREE.PMREMGenerator(renderer);
  // The project's map: row 0 the zenith, the middle column straight ahead (-z). three.js'
  // equirectangular lookup has v = 1 at the zenith and u = 1/2 + atan2(z, x) / 2 pi, a quarter
  // turn from the renderer's u = 1/2 + atan2(x, -z) / 2 pi: rows flipped, columns shifted by W/4.
  const environment = (rgb, w, h) => {
    const half = new Uint16Array(w * h * 4);
    for (let r = 0; r < h; ++r)
      for (let c = 0; c < w; ++c) {
        const src = ((h - 1 - r) * w + (c + w / 4) % w) * 3, dst = (r * w + c) * 4;
        for (let k = 0; k < 3; ++k) half[dst + k] = THREE.DataUtils.toHalfFloat(rgb[src + k]);
        half[dst + 3] = THREE.DataUtils.toHalfFloat(1);
      }
    const tex = new THREE.DataTexture(half, w, h, THREE.RGBAFormat, THREE.HalfFloatType);
    tex.mapping = THREE.EquirectangularReflectionMapping;
    tex.colorSpace = THREE.LinearSRGBColorSpace;
    tex.magFilter = THREE.LinearFilter;
    tex.minFilter = THREE.LinearFilter;
    tex.wrapS = THREE.RepeatWrapping;
    tex.needsUpdate = true;
    return {background: tex, environment: pmrem.fromEquirectangular(tex).texture};
  };
  const envs = viewData.envs.map((env) => {
    const bin = atob(env.rgb_f32_base64), bytes = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; ++i) bytes[i] = bin.charCodeAt(i);
    return environment(new Float32Array(bytes.buffer), env.width, env.height);
  });
  const scene = new THREE.Scene();
  const loader = new GLTFLoader();
  const fits = {};
  async function parse(base64) {
    const bin = atob(base64), bytes = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; ++i) bytes[i] = bin.charCodeAt(i);
    const gltf = await new Promise((ok, bad) => loader.parse(bytes.buffer, "", ok, bad));
    return gltf.scenes[0];  // scene 0: the sphere (scene 1: the plate)
  }
  for (const g of data.glbs) fits[g.key] = await parse(g.base64);
  // The project's view's camera: `render --scene sphere`'s pinhole (its data: tan of the half
  // field of view, distance along +z), square.
  const pinhole = (tanHalf, distance, aspect) => {
    const c = new THREE.PerspectiveCamera(2 * Math.atan(tanHalf) * 180 / Math.PI, aspect, 0.1, 20);
    c.position.set(0, 0, distance);
    c.lookAt(0, 0, 0);
    return c;
  };
  const viewCamera = pinhole(viewData.camera.tan_half_fov, viewData.camera.distance, 1);
  let camera = viewCamera;
  // The exposure: the project's view's slider (which starts at the report's sphere render's).
  const ex = document.getElementById("mbv-exposure");
  const state = {fit: data.glbs[0].key, env: 0,
                 exposure: Math.pow(2, ex ? Number(ex.value) : viewData.exposure_stops)};
  function draw() {
    scene.clear();
    scene.add(fits[state.fit]);
    scene.environment = envs[state.env].environment;
    scene.background = envs[state.env].background;
    renderer.toneMappingExposure = state.exposure;
    renderer.render(scene, camera);
    say(state.fit + ": " + data.glbs.find((g) => g.key === state.fit).file + " in three.js " +
        THREE.REVISION + " (GLTFLoader, MeshPhysicalMaterial), " + viewData.envs[state.env].name +
        ", exposure x" + state.exposure.toPrecision(3) + ".");
  }
  document.querySelectorAll("input[name=mbg-fit]").forEach((r) =>
    r.addEventListener("change", () => { state.fit = r.value; draw(); }));
  document.querySelectorAll("input[name=mbv-envmap]").forEach((r) =>
    r.addEventListener("change", () => { state.env = Number(r.value); draw(); }));
  if (ex) ex.addEventListener("input", () => { state.exposure = Math.pow(2, Number(ex.value)); draw(); });
  window.microbrdfGltf = {
    fits: data.glbs.map((g) => g.key),
    revision: THREE.REVISION,
    setFit: (k) => { state.fit = k; draw(); },
    // For the tests: another .glb (base64) shown as fit `key`.
    addGlb: async (key, base64) => {
      fits[key] = await parse(base64);
      data.glbs.push({key, file: key + ".glb"});
    },
    setExposure: (stops) => { state.exposure = Math.pow(2, stops); draw(); },
    // For the tests: `microbrdf render --scene sphere`'s pinhole camera (at (0, 0, distance),
    // looking at the origin, tan of the half field of view), at w x h pixels; no argument: back
    // to the page's view.
    usePinhole: (tanHalf, distance, w, h) => {
      if (tanHalf === undefined) {
        camera = viewCamera;
        renderer.setSize(384, 384, false);
      } else {
        camera = pinhole(tanHalf, distance, w / h);
        renderer.setSize(w, h, false);
      }
      draw();
    },
    draw
  };
  draw();
} catch (e) {
  say("The glTF view could not start: " + e.message);
  throw e;
}
)JS";

std::vector<std::uint8_t> read_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

GltfViewHtml gltf_view_html(const json& summary, const std::string& dir) {
  const EmbeddedThree three = embedded_three();
  json glbs = json::array();
  if (summary.contains("exports") && summary["exports"].contains("materials"))
    for (const auto& m : summary["exports"]["materials"]) {
      if (!m.contains("gltf") || !m["gltf"].contains("file")) continue;
      const std::string rel = m["gltf"]["file"].get<std::string>();
      const auto bytes = read_bytes(std::filesystem::path(dir) / rel);
      if (bytes.empty()) continue;
      glbs.push_back({{"key", m["model"]}, {"file", rel}, {"base64", base64(bytes)}});
    }
  GltfViewHtml h;
  if (!three.missing.empty() || glbs.empty()) {
    h.after =
        "<p class=\"note\" id=\"mbg-missing\">No glTF view (the exported file in three.js) "
        "in this report: " +
        escape(three.missing.empty() ? "this run exported no .glb" : three.missing) +
        ". The exported files are linked under Renderer-ready materials.</p>\n";
    return h;
  }
  std::string radios;
  for (std::size_t i = 0; i < glbs.size(); ++i) {
    const std::string k = glbs[i]["key"].get<std::string>();
    radios += "<label><input type=\"radio\" name=\"mbg-fit\" value=\"" + escape(k) + "\"" +
              (i == 0 ? " checked" : "") + "> " + escape(k) + "</label> ";
  }
  h.beside =
      "<div class=\"mbg\" style=\"width:386px\"><canvas id=\"mbg-canvas\" width=\"384\" "
      "height=\"384\" aria-label=\"sphere of the exported glTF file in three.js\"></canvas>"
      "\n<div class=\"mbv-controls\"><div><b>glTF file in three.js</b> " +
      radios +
      "</div>\n<p id=\"mbg-status\" class=\"cap\"><noscript>The glTF view needs "
      "JavaScript.</noscript></p></div></div>\n";
  h.after =
      "<p class=\"cap\" id=\"gltf-view\">Beside it, the fit's exported <code>.glb</code> "
      "(its sphere) as a standard real-time viewer shows it: three.js " +
      escape(three.version) +
      " (npm package <code>three</code>, embedded in this page) reads it with its "
      "GLTFLoader and draws its metallic-roughness material with "
      "<code>KHR_materials_anisotropy</code>, lit by the same environment (prefiltered by "
      "three.js' PMREMGenerator; the environment buttons and the exposure slider apply to "
      "both), same camera. Differences are glTF's and three.js': Schlick's Fresnel from the "
      "base colour instead of the exact conductor Fresnel, multiple-scattering energy "
      "compensation, image-based lighting by the split-sum approximation, a bent normal for "
      "anisotropy. Measured against microbrdf's path tracer under the courtyard map (mean "
      "luminance of the sphere, Cu): isotropic GGX alpha 0.02 +4.1 % (SSIM 0.995), alpha 0.05 "
      "+5.0 %, alpha 0.2 +20 %, anisotropic GGX of strength 0.19 +61 % (SSIM 0.85); under a "
      "uniform map within 1 % up to alpha 0.05 (docs/gltf.md).</p>\n";
  h.after += "<script type=\"application/json\" id=\"mbg-data\">" + json{{"glbs", glbs}}.dump() +
             "</script>\n";
  for (const auto& m : three.modules)
    h.after += "<script type=\"text/plain\" id=\"mbg-mod-" + std::string(m.name) +
               "\" data-npm=\"three@" + escape(three.version) + " " + m.path + "\">" + m.text +
               "</script>\n";
  h.after += "<script type=\"module\">" + std::string(kModuleScript) + "</script>\n";
  return h;
}

}  // namespace microbrdf::report
