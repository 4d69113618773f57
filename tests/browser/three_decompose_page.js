// The page of three_decompose.mjs (a module; `three` from an import map): three.js draws a .glb's
// sphere into a float target, without tone mapping, with its lighting chunk changed on request.
import * as THREE from "three";
import { GLTFLoader } from "three/addons/loaders/GLTFLoader.js";
import { EXRLoader } from "three/addons/loaders/EXRLoader.js";
import { HDRLoader } from "three/addons/loaders/HDRLoader.js";

const renderer = new THREE.WebGLRenderer({ canvas: document.getElementById("c"), antialias: false });
renderer.setPixelRatio(1);
renderer.toneMapping = THREE.NoToneMapping;
const pmrem = new THREE.PMREMGenerator(renderer);
const st = {};

// An .exr or .hdr as float RGBA, row 0 the top of the image.
async function loadImage(url) {
  const loader = url.endsWith(".exr") ? new EXRLoader() : new HDRLoader();
  loader.setDataType(THREE.FloatType);
  const r = loader.parse(await (await fetch(url)).arrayBuffer());
  const w = r.width, h = r.height, n = r.data.length / (w * h), out = new Float32Array(w * h * 4);
  for (let y = 0; y < h; ++y)  // (the loaders' flipY: whether their row 0 is the top)
    for (let i = 0; i < w; ++i)
      for (let k = 0; k < 4; ++k)
        out[4 * (y * w + i) + k] = k < n ? r.data[n * ((r.flipY ? y : h - 1 - y) * w + i) + k] : 1;
  return { w, h, rgba: out };
}

// GLSL: the environment in three.js' equirectangular texture, a radical inverse, Smith's Lambda.
const common = `
uniform sampler2D uEq;
vec3 eqLookup(vec3 dv) {  // a view-space direction
  return texture(uEq, equirectUv(normalize(transformDirectionByInverseViewMatrix(dv, viewMatrix)))).rgb;
}
float radInv(uint bits) {
  bits = (bits << 16u) | (bits >> 16u);
  bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
  bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
  bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
  bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
  return float(bits) * 2.3283064365386963e-10;
}
float lambdaGgx(float a2, float c) {
  c = clamp(c, 1e-6, 1.0);
  return 0.5 * (-1.0 + sqrt(1.0 + a2 * (1.0 - c * c) / (c * c)));
}
// The i-th of N GGX normals about n (density D(m) (m.n)).
vec3 ggxNormal(vec3 n, float a2, uint i, uint N) {
  vec3 up = abs(n.z) < 0.999 ? vec3(0.0, 0.0, 1.0) : vec3(1.0, 0.0, 0.0);
  vec3 t = normalize(cross(up, n)), b = cross(n, t);
  float u1 = (float(i) + 0.5) / float(N), ph = 6.28318530718 * radInv(i);
  float c2 = (1.0 - u1) / (1.0 + (a2 - 1.0) * u1);
  return sqrt(c2) * n + sqrt(1.0 - c2) * (cos(ph) * t + sin(ph) * b);
}`;

// The map prefiltered as the PMREM means to (the GGX lobe about r with v = n = r, weighted by
// n.l), exactly.
const prefilter = (n) => `
vec3 exactPrefilter(vec3 r, float rough) {
  float a = rough * rough, a2 = a * a;
  vec3 sum = vec3(0.0);
  float wsum = 0.0;
  for (uint i = 0u; i < ${n}u; ++i) {
    vec3 m = ggxNormal(r, a2, i, ${n}u);
    vec3 l = 2.0 * dot(r, m) * m - r;
    float nl = dot(r, l);
    if (nl <= 0.0) continue;
    sum += eqLookup(l) * nl;
    wsum += nl;
  }
  return sum / wsum;
}`;

// The reflected radiance of three.js' single-scattering BRDF (Schlick Fresnel with F0 and F90,
// height-correlated Smith G2) integrated over the map: f cos / pdf = F G2 (v.m) / ((n.v) (n.m)).
const integral = (n) => `
vec3 exactIntegral(vec3 n, vec3 v, float rough, vec3 f0, float f90) {
  float a = rough * rough, a2 = a * a, nv = dot(n, v);
  if (nv <= 0.0) return vec3(0.0);
  vec3 sum = vec3(0.0);
  for (uint i = 0u; i < ${n}u; ++i) {
    vec3 m = ggxNormal(n, a2, i, ${n}u);
    float vm = dot(v, m);
    if (vm <= 0.0) continue;
    vec3 l = 2.0 * vm * m - v;
    float nl = dot(n, l);
    if (nl <= 0.0) continue;
    float g2 = 1.0 / (1.0 + lambdaGgx(a2, nv) + lambdaGgx(a2, nl));
    vec3 F = f0 + (vec3(f90) - f0) * pow(1.0 - vm, 5.0);
    sum += F * g2 * vm / (nv * dot(n, m)) * eqLookup(l);
  }
  return sum / float(${n}u);
}`;

const single = "vec3 indirectSpecular = radiance * singleScattering;";

window.decompose = {
  // The map (renderer's orientation: row 0 the zenith, the middle column along -z) turned into
  // three.js' equirectangular one (rows flipped, columns shifted by a quarter), as the report does.
  async setEnvironment(url) {
    const { w, h, rgba } = await loadImage(url);
    const d = new Float32Array(w * h * 4);
    for (let r = 0; r < h; ++r)
      for (let c = 0; c < w; ++c)
        for (let k = 0; k < 4; ++k) d[(r * w + c) * 4 + k] = rgba[((h - 1 - r) * w + (c + w / 4) % w) * 4 + k];
    const tex = new THREE.DataTexture(d, w, h, THREE.RGBAFormat, THREE.FloatType);
    tex.mapping = THREE.EquirectangularReflectionMapping;
    tex.colorSpace = THREE.LinearSRGBColorSpace;
    tex.magFilter = tex.minFilter = THREE.LinearFilter;
    tex.wrapS = THREE.RepeatWrapping;
    tex.needsUpdate = true;
    st.eq = tex;
    st.env = pmrem.fromEquirectangular(tex).texture;
  },
  async loadGlb(url) {
    const buf = await (await fetch(url)).arrayBuffer();
    const g = await new Promise((ok, bad) => new GLTFLoader().parse(buf, "", ok, bad));
    st.obj = g.scenes[0];
    st.obj.traverse((o) => { if (o.isMesh) st.mat = o.material; });
  },
  // o: {noMS, prefilter: N, integral: N}. Linear RGB, row 0 the top.
  render(size, o) {
    const scene = new THREE.Scene();
    scene.add(st.obj);
    scene.environment = st.env;
    scene.background = st.eq;
    st.mat.onBeforeCompile = (shader) => {
      let chunk = THREE.ShaderChunk.lights_physical_pars_fragment;
      if (o.noMS) chunk = chunk.replace("indirectSpecular += multiScattering * cosineWeightedIrradiance;", "");
      if (o.prefilter) {
        chunk = common + prefilter(o.prefilter) + chunk.replace(single,
          "vec3 rv = normalize(mix(reflect(-geometryViewDir, geometryNormal), geometryNormal, " +
          "pow4(material.roughness)));\nvec3 indirectSpecular = exactPrefilter(rv, material.roughness) * singleScattering;");
      } else if (o.integral) {
        chunk = common + integral(o.integral) + chunk.replace(single,
          "vec3 indirectSpecular = exactIntegral(geometryNormal, geometryViewDir, material.roughness, " +
          "material.diffuseColor, material.specularF90);");
      }
      if (o.prefilter || o.integral) shader.uniforms.uEq = { value: st.eq };
      shader.fragmentShader = shader.fragmentShader.replace("#include <lights_physical_pars_fragment>", chunk);
    };
    st.mat.customProgramCacheKey = () => JSON.stringify(o);
    st.mat.needsUpdate = true;
    const camera = new THREE.PerspectiveCamera(2 * Math.atan(1.15 / 4) * 180 / Math.PI, 1, 0.1, 20);
    camera.position.set(0, 0, 4);
    camera.lookAt(0, 0, 0);
    const target = new THREE.WebGLRenderTarget(size, size, { type: THREE.FloatType });
    renderer.setRenderTarget(target);
    renderer.render(scene, camera);
    const px = new Float32Array(size * size * 4);
    renderer.readRenderTargetPixels(target, 0, 0, size, size, px);
    renderer.setRenderTarget(null);
    target.dispose();
    const out = new Array(size * size * 3);
    for (let y = 0; y < size; ++y)
      for (let x = 0; x < size; ++x)
        for (let k = 0; k < 3; ++k) out[(y * size + x) * 3 + k] = px[((size - 1 - y) * size + x) * 4 + k];
    return out;
  },
  // The path tracer's .exr: linear RGB, row 0 the top.
  async exrPixels(url) {
    const { w, h, rgba } = await loadImage(url);
    const px = new Array(w * h * 3);
    for (let i = 0; i < w * h; ++i) for (let k = 0; k < 3; ++k) px[3 * i + k] = rgba[4 * i + k];
    return { w, h, px };
  },
};
