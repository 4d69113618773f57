// Where three.js' render of a GGX .glb differs from `microbrdf render`'s, one suspect at a time
// (docs/gltf.md, "In a glTF viewer": the table of suspects). Not a test: a measuring tool.
//
//   node three_decompose.mjs BIN ENVMAP METAL ALPHA...
//
// ENVMAP: an equirectangular .hdr or .exr in the renderer's orientation (row 0 the zenith), or
// "uniform" (radiance 0.5 everywhere). For each isotropic GGX ALPHA it exports the .glb
// (`export gltf`), renders `render --scene sphere` (64 paths per pixel, --brushing rotational, as
// the file's sphere) with the exact conductor Fresnel and with --fresnel schlick into .exr, and
// draws the .glb with three.js (report-js/node_modules/three, the version the report embeds) in
// headless Chromium into a float target, no tone mapping, the same pinhole camera. It prints
// three.js' mean luminance over the sphere's inner 95 % relative to the path tracer's, also on
// the sphere's centre (inside 60 % of the radius) and its rim, for three.js as it is and with its
// shader chunks changed through onBeforeCompile (what the report never does):
//   - "no multiple scattering": without the energy-compensation term;
//   - "exact V = N prefilter": the PMREM replaced by an exact GGX prefilter of the map (1024
//     directions), still split-sum: the PMREM's own error;
//   - "exact integral": radiance x DFG replaced by the integral of three.js' own single-scattering
//     BRDF (Schlick Fresnel from the base colour, height-correlated Smith G2) over the map with
//     1024 GGX-sampled directions per pixel: what remains is glTF's BRDF, not the lighting;
// and the last against the Schlick path tracer: what remains is RGB against spectral rendering.
// Needs what the browser test needs (Chromium, puppeteer-core here, three.js in report-js).
import { execFileSync } from "node:child_process";
import fs from "node:fs";
import http from "node:http";
import os from "node:os";
import path from "node:path";
import puppeteer from "puppeteer-core";

const [bin, envmap, metal, ...alphas] = process.argv.slice(2);
if (!bin || !envmap || !metal || alphas.length === 0) {
  console.error("usage: node three_decompose.mjs BIN ENVMAP|uniform METAL ALPHA...");
  process.exit(2);
}
const here = path.dirname(new URL(import.meta.url).pathname);
const threeDir = path.resolve(here, "../../report-js/node_modules/three");
const chromium = process.env.CHROMIUM || "/usr/bin/chromium";
const tmp = fs.mkdtempSync(path.join(os.tmpdir(), "three-decompose-"));
const size = 128;

// The page: three.js from its npm folder through an import map, the map and the images from tmp.
const page_html = `<!doctype html><canvas id="c" width="${size}" height="${size}"></canvas>
<script type="importmap">{"imports": {"three": "/three/build/three.module.js",
  "three/addons/": "/three/examples/jsm/"}}</script>
<script type="module">${fs.readFileSync(path.join(here, "three_decompose_page.js"), "utf8")}</script>`;
const server = http.createServer((req, res) => {
  const u = decodeURIComponent(req.url.split("?")[0]);
  const file = u.startsWith("/three/") ? path.join(threeDir, u.slice(7))
             : u.startsWith("/f/") ? path.join(tmp, path.basename(u)) : null;
  if (u === "/") {
    res.writeHead(200, { "content-type": "text/html" });
    return res.end(page_html);
  }
  if (!file || !fs.existsSync(file)) {
    res.writeHead(404);
    return res.end();
  }
  res.writeHead(200, { "content-type": file.endsWith(".js") ? "text/javascript" : "application/octet-stream" });
  fs.createReadStream(file).pipe(res);
});
await new Promise((ok) => server.listen(0, "127.0.0.1", ok));
const browser = await puppeteer.launch({
  executablePath: chromium, headless: true,
  args: ["--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist"],
});
try {
  const page = await browser.newPage();
  page.on("pageerror", (e) => console.log("page error: " + e.message));
  await page.goto(`http://127.0.0.1:${server.address().port}/`);
  await page.waitForFunction(() => window.decompose !== undefined, { timeout: 120000 });
  let lights;
  if (envmap === "uniform") {
    // A Radiance file of 0.5 everywhere for three.js (0.5 is exact in RGBE); the path tracer's own.
    const px = Buffer.alloc(128 * 64 * 4);
    for (let i = 0; i < 128 * 64; ++i) px.set([128, 128, 128, 128], 4 * i);
    fs.writeFileSync(path.join(tmp, "env.hdr"), Buffer.concat([
      Buffer.from("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 64 +X 128\n"), px]));
    lights = ["--white-env", "--env-scale", "0.5"];
  } else {
    fs.copyFileSync(envmap, path.join(tmp, "env" + path.extname(envmap)));
    lights = ["--envmap", envmap];
  }
  await page.evaluate((u) => window.decompose.setEnvironment(u),
                      "/f/env" + (envmap === "uniform" ? ".hdr" : path.extname(envmap)));
  const render = (alpha, fresnel) => {
    const out = path.join(tmp, `pt_${alpha}_${fresnel}.exr`);
    execFileSync(bin, ["render", "--scene", "sphere", "--model", "ggx", "--alpha", alpha, "--metal", metal,
                       "--fresnel", fresnel, ...lights, "--brushing", "rotational", "--size", String(size),
                       "--spp", "64", "--quiet", "-o", out], { stdio: "ignore" });
    return page.evaluate((u) => window.decompose.exrPixels(u), "/f/" + path.basename(out));
  };
  const rad = Math.tan(Math.asin(0.25)) / (1.15 / 4);  // the silhouette, asin(1/4) seen from 4
  const lum = (px, k) => 0.2126 * px[3 * k] + 0.7152 * px[3 * k + 1] + 0.0722 * px[3 * k + 2];
  const rel = (a, b, inside) => {
    let sa = 0, sb = 0;
    for (let y = 0; y < size; ++y)
      for (let x = 0; x < size; ++x) {
        const r = Math.hypot(2 * (x + 0.5) / size - 1, 2 * (y + 0.5) / size - 1) / rad;
        if (r < 0.95 && inside(r)) { sa += lum(a, y * size + x); sb += lum(b, y * size + x); }
      }
    const v = 100 * (sa / sb - 1);
    return (v >= 0 ? "+" : "") + v.toFixed(2) + " %";
  };
  const line = (label, a, b) =>
    console.log(`  ${label.padEnd(46)} ${rel(a, b, () => true).padStart(9)}   centre ` +
                `${rel(a, b, (r) => r < 0.6).padStart(9)}   rim ${rel(a, b, (r) => r >= 0.6).padStart(9)}`);
  for (const alpha of alphas) {
    const glb = path.join(tmp, `ggx_${alpha}.glb`);
    execFileSync(bin, ["export", "gltf", "--model", "ggx", "--alpha", alpha, "--metal", metal, "-o", glb],
                 { stdio: "ignore" });
    await page.evaluate((u) => window.decompose.loadGlb(u), "/f/" + path.basename(glb));
    const exact = await render(alpha, "exact"), schlick = await render(alpha, "schlick");
    const three = (o) => page.evaluate((s, o) => window.decompose.render(s, o), size, o);
    console.log(`GGX alpha ${alpha}, ${metal}, ${envmap}: three.js against the path tracer (mean luminance)`);
    line("three.js as the report shows it", await three({}), exact.px);
    line("no multiple scattering", await three({ noMS: true }), exact.px);
    line("no multiple scattering, exact V = N prefilter", await three({ noMS: true, prefilter: 1024 }), exact.px);
    const integral = await three({ noMS: true, integral: 1024 });
    line("no multiple scattering, exact integral", integral, exact.px);
    line("the same against the Schlick path tracer", integral, schlick.px);
  }
} finally {
  await browser.close();
  server.close();
  fs.rmSync(tmp, { recursive: true, force: true });
}
