// `microbrdf render`: preview images of a BRDF on objects under environment maps and lights
// (the spectral path tracer of include/microbrdf/render.hpp).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <sstream>

#include "cli_common.hpp"
#include "cli_threads.hpp"
#include "commands.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/microscene.hpp"
#include "microbrdf/render.hpp"
#include "microbrdf/texture.hpp"
#include "microbrdf/units.hpp"
#include "render_lights.hpp"
#include "render_sun.hpp"
#include "spec_flags.hpp"

namespace microbrdf::cli {
namespace {

struct RenderArgs {
  SpecFlags spec;  // BRDF and material
  std::string scene = "cylinders", obj, brushing = "linear", brush_angle = "0", micro_scene;
  double micro_tiles = RenderScene{}.micro_tiles;
  sun2002::SunRenderOptions sun;  // Sun 2002 options (Figs. 8 and 11)
  double uv_scale = 1;
  RenderLightFlags lights;
  // image
  int size = 256, width = 0, height = 0, spp = 64, max_depth = 6,
      wavelengths = RenderOptions{}.wavelengths, threads = 0;
  std::uint64_t seed = 1;
  std::string mis = "mis", sampler = "sobol";
  std::string direct = direct_light_name(RenderOptions{}.direct);
  std::string ris_candidates = std::to_string(RenderOptions{}.ris_brdf_candidates) + "," +
                               std::to_string(RenderOptions{}.ris_light_candidates);
  double exposure = 0;
  bool normalize = false;
  std::vector<std::string> outputs;
  bool json = false, quiet = false;
};

/// Everything cheap, before any file is parsed or a ray is traced: outputs, input files, the
/// environment map's signature, the metal, image settings.
void preflight(const RenderArgs& a) {
  if (a.outputs.empty())
    throw InputError("give an output: -o image.png, -o image.exr and/or -o image.npy");
  Preflight pre;
  for (const auto& o : a.outputs) pre.output("-o", o, {".png", ".exr", ".npy"});
  if (!a.lights.envmap.empty()) pre.envmap("--envmap", a.lights.envmap);
  check_spec_files(pre, a.spec);
  if (!a.obj.empty()) pre.input("--obj", a.obj);
  if (!a.micro_scene.empty()) pre.input("--micro-scene", a.micro_scene);
  if (!a.sun.s_texture.empty()) pre.input("--s-texture", a.sun.s_texture);
  if (!a.sun.color_texture.empty()) pre.input("--color-texture", a.sun.color_texture);
  pre.done();
  (void)parse_render_sampler(a.sampler, "--sampler");
  if (a.micro_scene.empty() && a.micro_tiles != RenderScene{}.micro_tiles)
    throw InputError("--micro-tiles: only with --micro-scene");
  if (!a.micro_scene.empty()) {
    if (a.scene != "plate") throw InputError("--micro-scene goes with --scene plate");
    if (!a.spec.keys().empty() || a.sun.given() || !a.sun.s_texture.empty())
      throw InputError(
          "--micro-scene draws the micro-scene's own materials: leave out the BRDF and "
          "material flags");
    return;
  }
  (void)render_brdf_spec(a.spec, a.sun);  // the BRDF and material flags, before any file
  (void)material_spec(a.spec, MaterialSpec::named_metal("Al"));
  warn_single_dk_table(a.spec, "render");
}

void run(RenderArgs& a) {
  preflight(a);
  RenderScene sc;
  sc.kind = parse_preview_scene(a.scene);
  sc.obj_path = a.obj;
  if (!a.obj.empty() && sc.kind != PreviewScene::Obj)
    throw InputError("--obj goes with --scene obj");
  if (a.brushing == "linear")
    sc.brushing = Brushing::Linear;
  else if (a.brushing == "rotational")
    sc.brushing = Brushing::Rotational;
  else
    throw InputError("--brushing must be linear or rotational");
  sc.brush_angle_rad = parse_angle(a.brush_angle);
  sc.uv_scale = a.uv_scale;
  sc.micro_tiles = a.micro_tiles;
  std::vector<std::shared_ptr<const Svbrdf>> mats;
  if (!a.micro_scene.empty()) {
    sc.micro_scene = std::make_shared<MicroSceneDesc>(load_micro_scene(a.micro_scene));
    mats = micro_scene_materials(*sc.micro_scene);
  } else {
    mats = render_materials(a.spec, a.sun);
  }
  RenderOptions opt;
  opt.width = a.width > 0 ? a.width : a.size;
  opt.height = a.height > 0 ? a.height : a.size;
  opt.spp = a.spp;
  opt.max_depth = a.max_depth;
  opt.wavelengths = a.wavelengths;
  opt.seed = a.seed;
  opt.threads = bounded_threads("render", a.threads);
  opt.exposure = a.exposure;
  opt.mis = parse_mis_mode(a.mis, "--mis");
  opt.sampler = parse_render_sampler(a.sampler, "--sampler");
  opt.direct = parse_direct_light(a.direct, "--direct");
  parse_ris_candidates(a.ris_candidates, "--ris-candidates", opt);
  const auto lights = make_lights(a.lights, sc.kind);
  Progress progress("render", a.quiet);
  if (!a.quiet) opt.progress = progress.fraction_callback();
  const RenderImage img = render(sc, mats, lights, opt);
  const double png_exposure = a.exposure + (a.normalize ? normalizing_exposure(img) : 0.0);
  for (const auto& o : a.outputs) {
    std::string ext = o.size() >= 4 ? o.substr(o.size() - 4) : "";
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char ch) { return std::tolower(ch); });
    if (ext == ".exr")
      write_render_exr(img, o);
    else if (ext == ".npy")
      write_render_npy(img, o);
    else
      write_render_png(img, o, png_exposure);
  }
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < img.rgb.size() / 3; ++i)
    mean += Eigen::Vector3d(img.rgb[3 * i], img.rgb[3 * i + 1], img.rgb[3 * i + 2]);
  mean /= double(img.rgb.size() / 3);
  if (a.json) {
    print_json({{"outputs", a.outputs},
                {"scene", a.scene},
                {"width", img.width},
                {"height", img.height},
                {"spp", opt.spp},
                {"seed", opt.seed},
                {"threads", opt.threads},
                {"wavelengths_per_path", opt.wavelengths},
                {"max_depth", opt.max_depth},
                {"mis", a.mis},
                {"sampler", render_sampler_name(opt.sampler)},
                {"direct", direct_light_name(opt.direct)},
                {"seconds", img.seconds},
                {"samples_per_second", img.samples_per_second},
                {"rays", img.rays},
                {"rays_per_second", double(img.rays) / std::max(img.seconds, 1e-9)},
                {"mean_linear_srgb", {mean[0], mean[1], mean[2]}},
                {"png_exposure", png_exposure},
                {"settings", img.settings}});
  } else {
    std::printf("%s\n  %dx%d, %d spp in %.2f s (%.3g samples/s, %.3g rays/s); wrote",
                img.settings.c_str(), img.width, img.height, opt.spp, img.seconds,
                img.samples_per_second, double(img.rays) / std::max(img.seconds, 1e-9));
    for (const auto& o : a.outputs) std::printf(" %s", o.c_str());
    std::printf("\n");
  }
}

}  // namespace

void register_render(CLI::App& app) {
  auto a = std::make_shared<RenderArgs>();
  auto* c = app.add_subcommand(
      "render", "Preview images of a BRDF on objects under environment maps and lights");
  c->footer(
      std::string(
          "A spectral path tracer (Embree 3): hero wavelengths 360-830 nm, next-event estimation "
          "and\n"
          "BRDF sampling combined by multiple importance sampling (power heuristic). Output: "
          "linear\n"
          "sRGB (D65) radiance in .exr, tone-mapped sRGB in .png (--exposure stops, then "
          "clipped).\n"
          "Scenes: cylinders (Dong 2015 Fig. 10: two cylinder sections, the brushing direction\n"
          "horizontal on the left and vertical on the right), plate (Dong Fig. 13: seen from "
          "above,\n"
          "a disk light spanning 9 deg, 23 deg to the left, unless lights are given), sphere, "
          "vase\n"
          "(a surface of revolution), obj (--obj FILE.obj), furnace_sphere.\n"
          "World frame: y up, the camera looks along -z (the plate: down -y, image up = -z).\n"
          "Lights: --envmap FILE (.exr or Radiance .hdr, equirectangular, row 0 = zenith, the "
          "middle\n"
          "column straight ahead of the camera); --point X,Y,Z:R,G,B (intensity, W/sr per "
          "channel);\n"
          "--sphere-light X,Y,Z,RADIUS:R,G,B and --disk-light X,Y,Z,NX,NY,NZ,RADIUS:R,G,B "
          "(radiance);\n"
          "with no light at all, a uniform white sky. Radiance 1 = D65 white of luminance 1.\n"
          "BRDFs: microfacet (--model/--alpha* or --ndf FILE), Kirchhoff (--kirchhoff DK.npy), "
          "Sun\n"
          "2002 (--sun S), --mirror, each with a material's Fresnel term (--metal, default Al; "
          "--n/--k;\n"
          "--nk-csv; --r0; --color; --fresnel); --lambertian A; an SH-matrix BRDF (--sh "
          "FILE.shbrdf,\n"
          "grey, its own reflectance); an ellipsoid parameter texture (--texture TEX.exr from\n"
          "`microbrdf texture`, each texel's fit with the material's Fresnel term; --uv-scale =\n"
          "texture repeats per scene unit).\n"
          "--micro-scene SCENE.json (with --scene plate) draws the micro-scene that `microbrdf\n"
          "simulate` traces as geometry, with its own materials, repeated over the plate\n"
          "(--micro-tiles tiles across it; its x axis follows --brush-angle as a BRDF's "
          "would).\n") +
      kRenderSunHelp +
      "The BRDF's x axis follows --brushing linear (the image's horizontal turned by\n"
      "--brush-angle about the normal) or rotational (circles about the object's axis).\n\n"
      "Examples:\n"
      "  microbrdf render --scene cylinders --model beckmann --alpha-x 0.007 --alpha-y 0.14 \\\n"
      "      --metal Fe --envmap courtyard.exr --size 256 --spp 64 -o brushed.png\n"
      "  microbrdf render --scene plate --ndf stainless4_ndf.npy --metal SS-austenitic -o p.png\n"
      "  microbrdf render --scene sphere --sun 5 --metal Cu --point 0,0,4:20 -o cu.png --json\n"
      "  microbrdf render --scene cylinders --texture ss4_tex.exr --uv-scale 2 --metal Fe -o "
      "t.png\n"
      "  microbrdf render --scene sphere --sh ggx.shbrdf --spp 64 -o sh.png\n"
      "  microbrdf render --scene plate --micro-scene cylinders.json --micro-tiles 4 -o cyl.png\n"
      "  microbrdf render --scene vase --model ggx --alpha 0.2 --metal Au --brushing rotational "
      "\\\n"
      "      --envmap studio.hdr --spp 256 --threads 2 -o vase.exr -o vase.png");
  c->add_option("--scene", a->scene, "cylinders, plate, sphere, vase, obj or furnace_sphere")
      ->capture_default_str();
  c->add_option("--obj", a->obj, "OBJ mesh for --scene obj (centred, scaled to 2 units)");
  c->add_option("--micro-scene", a->micro_scene,
                "Micro-scene JSON (as for simulate) drawn as geometry on the plate, with its "
                "own materials, instead of a BRDF");
  c->add_option("--micro-tiles", a->micro_tiles,
                "Tiles of the --micro-scene across the plate (2 scene units)")
      ->capture_default_str()
      ->check(positive_number(1e9));
  c->add_option("--brushing", a->brushing, "Tangent field: linear or rotational")
      ->capture_default_str();
  c->add_option("--brush-angle", a->brush_angle, "Turn of the brushing direction about n (deg)")
      ->capture_default_str()
      ->check(direction());
  c->add_option("--uv-scale", a->uv_scale, "Texture repeats per scene unit")
      ->capture_default_str()
      ->check(positive_number(1e6));
  add_brdf_flags(c, a->spec, kFlagAllBrdfs | kFlagTexture);
  add_material_flags(c, a->spec, "default: Al");
  add_render_sun_flags(c, a->sun);
  add_render_light_flags(c, a->lights);
  c->add_option("--size", a->size, "Image width and height in pixels")
      ->capture_default_str()
      ->check(count_in(1, 16384));
  c->add_option("--width", a->width, "Image width (overrides --size)")->check(count_in(1, 16384));
  c->add_option("--height", a->height, "Image height (overrides --size)")
      ->check(count_in(1, 16384));
  c->add_option("--spp", a->spp, "Samples per pixel")
      ->capture_default_str()
      ->check(count_in(1, 1 << 20));
  c->add_option("--max-depth", a->max_depth, "Most bounces per path")->capture_default_str();
  c->add_option("--wavelengths", a->wavelengths, "Hero wavelengths per path (1..16)")
      ->capture_default_str();
  c->add_option("--seed", a->seed, "Random seed (same seed = same image, any thread count)")
      ->capture_default_str();
  c->add_option("--threads", a->threads, "Threads (0 = all cores)")->capture_default_str();
  c->add_option("--mis", a->mis, "mis (power heuristic), brdf (BRDF sampling only) or light")
      ->capture_default_str();
  c->add_option("--sampler", a->sampler,
                "sobol (Owen-scrambled Sobol' points, stratified per pixel) or independent "
                "(plain Monte Carlo)")
      ->capture_default_str();
  c->add_option("--direct", a->direct,
                "Direct light (--mis mis): mis (light + BRDF sample, power heuristic) or ris "
                "(resampled: --ris-candidates directions without rays, one chosen by its "
                "unshadowed light, one shadow ray; less noise at equal time; docs/render.md)")
      ->capture_default_str();
  c->add_option("--ris-candidates", a->ris_candidates,
                "With --direct ris: M,N = BRDF-sampled and light-sampled candidate directions per "
                "shading point (M 1..16, N 1..4; more: less noise, more work per bounce)")
      ->capture_default_str();
  c->add_option("--exposure", a->exposure, "Exposure of the PNG, stops")
      ->capture_default_str()
      ->check(number_in(-64, 64));
  c->add_flag("--normalize", a->normalize,
              "Scale the PNG so that its brightest pixels (99.9th percentile of the largest "
              "channel) are white, as Sun 2002 scales each image; --exposure adds to it");
  c->add_option(
      "-o,--output", a->outputs,
      "Output .png, .exr and/or .npy (linear sRGB, float64 (height, width, 3)); repeatable");
  c->add_flag("--json", a->json, "Print a JSON summary (timing, rays) on stdout");
  c->add_flag("--quiet", a->quiet, "No progress on stderr");
  c->callback([a] { run_guarded("render", [&] { run(*a); }); });
}

}  // namespace microbrdf::cli
