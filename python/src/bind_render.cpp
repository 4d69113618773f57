// The preview renderer (image as a numpy view) and the whole predict pipeline (summary dict).
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "microbrdf/brdf.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/kirchhoff.hpp"
#include "microbrdf/memory_budget.hpp"
#include "microbrdf/predict.hpp"
#include "microbrdf/render.hpp"

namespace microbrdf::python {
namespace {

Eigen::Vector3d vec3(const py::handle& obj, const char* what) {
  auto seq = obj.cast<py::sequence>();
  if (seq.size() != 3) throw py::value_error(std::string(what) + ": expected 3 numbers");
  return {seq[0].cast<double>(), seq[1].cast<double>(), seq[2].cast<double>()};
}

RenderLights lights(PreviewScene kind, const py::object& envmap, double env_scale,
                    double env_rotation, bool white_env, const py::list& points,
                    const py::list& spheres, const py::list& disks, bool defaults = true) {
  RenderLights l;
  if (!envmap.is_none()) l.envmap_path = fspath(envmap, "envmap");
  l.envmap_scale = env_scale;
  l.envmap_rotation_rad = env_rotation;
  l.uniform_white_env = white_env;
  for (auto p : points) {
    auto t = p.cast<py::sequence>();
    if (t.size() != 2) throw py::value_error("point: ((x, y, z), (r, g, b)) per light");
    l.points.push_back({vec3(t[0], "point position"), vec3(t[1], "point intensity")});
  }
  for (auto p : spheres) {
    auto t = p.cast<py::sequence>();
    if (t.size() != 3) throw py::value_error("sphere_light: ((x, y, z), radius, (r, g, b))");
    const double r = t[1].cast<double>();
    if (!(r > 0)) throw InputError("sphere_light: the radius must be > 0");
    l.spheres.push_back({vec3(t[0], "sphere_light centre"), r, vec3(t[2], "sphere_light rgb")});
  }
  for (auto p : disks) {
    auto t = p.cast<py::sequence>();
    if (t.size() != 4)
      throw py::value_error("disk_light: ((x, y, z), (nx, ny, nz), radius, (r, g, b))");
    const double r = t[2].cast<double>();
    if (!(r > 0)) throw InputError("disk_light: the radius must be > 0");
    l.disks.push_back({vec3(t[0], "disk_light centre"), vec3(t[1], "disk_light normal"), r,
                       vec3(t[3], "disk_light rgb")});
  }
  if (defaults) add_default_light_if_none(l, kind);  // (as the CLI)
  return l;
}

py::object render_image(const py::object& brdfs, const std::string& scene, int size, int width,
                        int height, int spp, int max_depth, int wavelengths, std::uint64_t seed,
                        int threads, const std::string& mis, const std::string& sampler,
                        const py::object& envmap, double env_scale, double env_rotation,
                        bool white_env, const py::list& point, const py::list& sphere_light,
                        const py::list& disk_light, const std::string& brushing, double brush_angle,
                        const py::object& obj, double uv_scale, const py::object& progress,
                        const std::string& direct, int ris_brdf_candidates,
                        int ris_light_candidates, const py::object& variants,
                        const std::vector<double>& variant_weights, const py::object& light_sets) {
  RenderScene sc;
  sc.kind = parse_preview_scene(scene);
  if (!obj.is_none()) sc.obj_path = fspath(obj, "obj");
  if (brushing == "linear")
    sc.brushing = Brushing::Linear;
  else if (brushing == "rotational")
    sc.brushing = Brushing::Rotational;
  else
    throw InputError("brushing must be 'linear' or 'rotational'");
  sc.brush_angle_rad = brush_angle;
  sc.uv_scale = uv_scale;
  // A Brdf, or a list of them (one per object): one variant's materials.
  auto materials = [](const py::handle& b) {
    std::vector<std::shared_ptr<const Svbrdf>> mats;
    if (py::isinstance<Brdf>(b)) {
      mats.push_back(std::make_shared<UniformSvbrdf>(b.cast<std::shared_ptr<Brdf>>()));
    } else {
      for (auto x : b.cast<py::sequence>())
        mats.push_back(std::make_shared<UniformSvbrdf>(x.cast<std::shared_ptr<Brdf>>()));
    }
    return mats;
  };
  std::vector<std::vector<std::shared_ptr<const Svbrdf>>> all{materials(brdfs)};
  if (!variants.is_none())
    for (auto v : variants.cast<py::sequence>()) all.push_back(materials(v));
  RenderOptions o;
  o.width = width > 0 ? width : size;
  o.height = height > 0 ? height : size;
  o.spp = spp;
  o.max_depth = max_depth;
  o.wavelengths = wavelengths;
  o.seed = seed;
  o.threads = threads;
  o.mis = parse_mis_mode(mis, "mis");
  o.sampler = parse_render_sampler(sampler, "sampler");
  o.direct = parse_direct_light(direct, "direct");
  o.ris_brdf_candidates = ris_brdf_candidates;
  o.ris_light_candidates = ris_light_candidates;
  o.variant_weights = variant_weights;
  o.progress = progress_hook<double>(progress);
  std::vector<RenderLights> sets{
      lights(sc.kind, envmap, env_scale, env_rotation, white_env, point, sphere_light, disk_light)};
  if (!light_sets.is_none())
    for (auto item : light_sets.cast<py::sequence>()) {
      const auto d = item.cast<py::dict>();
      for (auto kv : d) {
        const auto key = kv.first.cast<std::string>();
        if (key != "envmap" && key != "env_scale" && key != "env_rotation" && key != "white_env" &&
            key != "point")
          throw py::value_error("light_sets: unknown key '" + key +
                                "' (envmap, env_scale, env_rotation, white_env, point)");
      }
      auto get = [&](const char* k, py::object fallback) {
        return d.contains(k) ? py::reinterpret_borrow<py::object>(d[k]) : fallback;
      };
      RenderLights extra = lights(sc.kind, get("envmap", py::none()),
                                  get("env_scale", py::float_(1.0)).cast<double>(),
                                  get("env_rotation", py::float_(0.0)).cast<double>(),
                                  get("white_env", py::bool_(false)).cast<bool>(),
                                  get("point", py::list()), py::list(), py::list(),
                                  false);  // (an empty set is an error, not a white sky)
      sets.push_back(std::move(extra));
    }
  // Every image the call returns, float RGB: within the memory budget before anything runs.
  if (o.width > 0 && o.height > 0)
    check_count("size", mul_sat(std::uint64_t(o.width), std::uint64_t(o.height)),
                3 * sizeof(float) * (all.size() + sets.size() - 1), "the images");
  auto* imgs = new std::vector<RenderImage>;
  py::capsule owner(imgs, [](void* p) { delete static_cast<std::vector<RenderImage>*>(p); });
  *imgs = call_released([&] {
    if (variants.is_none() && sets.size() == 1)
      return std::vector<RenderImage>{render(sc, all.front(), sets.front(), o)};
    return render_light_sets(sc, all, sets, o);
  });
  auto image = [&](const RenderImage& img) -> py::object {
    return view(img.rgb.data(), {img.height, img.width, 3}, owner);
  };
  // One light set: an image or a list per variant; several: that, then one image per further
  // set (the first BRDF under it).
  py::object first;
  if (variants.is_none()) {
    first = image(imgs->front());
  } else {
    py::list per_variant;
    for (std::size_t v = 0; v < all.size(); ++v) per_variant.append(image((*imgs)[v]));
    first = per_variant;
  }
  if (light_sets.is_none()) return first;
  py::list out;
  out.append(first);
  for (std::size_t l = 1; l < sets.size(); ++l) out.append(image((*imgs)[all.size() + l - 1]));
  return out;
}

py::object predict_run(
    const py::object& inputs, const py::object& out_dir, const std::string& metal,
    const py::object& filter_sigma, std::size_t resolution, bool kirchhoff, double wavelength,
    const py::object& patch, const std::vector<double>& theta_i, const py::object& envmap,
    double envmap_scale, int render_width, int spp, bool no_render, const std::string& renders,
    const py::object& strips, double texel, std::size_t texture_size, std::uint64_t seed,
    int threads, const std::string& level, const py::object& spacing, const std::string& render_ndf,
    std::size_t sweep_resolution, const py::object& progress, const std::string& integration,
    std::size_t supersample, const std::string& window, const std::string& theory) {
  PredictOptions o;
  o.kirchhoff_options.integration = parse_kirchhoff_integration(integration);
  o.kirchhoff_options.supersample = supersample;
  o.kirchhoff_options.window = parse_kirchhoff_window(window);
  if (wavelength > 0)  // a bad wavelength is refused below, naming it
    o.kirchhoff_options.stack_wavelengths_q = kirchhoff_stack_layers("visible", wavelength);
  o.inputs = path_list(inputs, "inputs");
  o.read = read_options(spacing);
  o.leveling = LevelingSpec::parse(level);
  o.material = MaterialSpec::named_metal(metal);
  if (py::isinstance<py::str>(filter_sigma)) {
    if (filter_sigma.cast<std::string>() != "auto")
      throw py::value_error("filter_sigma: metres, or 'auto'");
    o.filter_sigma_auto = true;
  } else {
    o.filter_sigma_m = filter_sigma.cast<double>();
  }
  o.filter_sigma_sweep_resolution = sweep_resolution;
  o.render_ndf = render_ndf;
  o.theory = theory;
  o.ndf_resolution = resolution;
  o.kirchhoff = kirchhoff;
  o.wavelength_m = wavelength;
  if (auto p = length_pair(patch, "patch")) {
    o.kirchhoff_options.patch_x = p->first;
    o.kirchhoff_options.patch_y = p->second;
  }
  if (!theta_i.empty()) o.slice_theta_i_rad = theta_i;
  if (!envmap.is_none()) o.envmap_path = fspath(envmap, "envmap");
  o.envmap_scale = envmap_scale;
  if (renders != "all" && renders != "measured" && renders != "none")
    throw InputError("renders '" + renders + "': give 'all', 'measured' or 'none'");
  o.render = !no_render && renders != "none";
  o.render_models = renders == "all";
  o.render_width = render_width;
  o.render_spp = spp;
  if (!strips.is_none()) {
    auto s = strips.cast<py::sequence>();
    if (s.size() != 2) throw py::value_error("strips: (along, across), each a path or a list");
    o.strips_along = path_list(s[0], "strips");
    o.strips_across = path_list(s[1], "strips");
  }
  o.texel_m = texel;
  o.texture_size = texture_size;
  o.seed = seed;
  o.threads = threads;
  o.log = progress_hook<const std::string&>(progress);
  const std::string dir = fspath(out_dir, "out_dir");
  const nlohmann::json summary = call_released([&] {
    nlohmann::json j = predict(o, dir).summary;
    kirchhoff_release_buffers();  // D_K's kept buffers: 100 MB and more in a Python session
    return j;
  });
  return json_to_py(summary);
}

}  // namespace

void bind_render(py::module_& m) {
  m.def("render", &render_image, py::arg("brdf"), py::arg("scene") = "cylinders",
        py::arg("size") = 256, py::arg("width") = 0, py::arg("height") = 0, py::arg("spp") = 16,
        py::arg("max_depth") = 6, py::arg("wavelengths") = RenderOptions{}.wavelengths,
        py::arg("seed") = 1, py::arg("threads") = 0, py::arg("mis") = "mis",
        py::arg("sampler") = "sobol", py::arg("envmap") = py::none(), py::arg("env_scale") = 1.0,
        py::arg("env_rotation") = 0.0, py::arg("white_env") = false, py::arg("point") = py::list(),
        py::arg("sphere_light") = py::list(), py::arg("disk_light") = py::list(),
        py::arg("brushing") = "linear", py::arg("brush_angle") = 0.0, py::arg("obj") = py::none(),
        py::arg("uv_scale") = 1.0, py::arg("progress") = py::none(),
        py::arg("direct") = direct_light_name(RenderOptions{}.direct),
        py::arg("ris_brdf_candidates") = RenderOptions{}.ris_brdf_candidates,
        py::arg("ris_light_candidates") = RenderOptions{}.ris_light_candidates,
        py::arg("variants") = py::none(), py::arg("variant_weights") = std::vector<double>{},
        py::arg("light_sets") = py::none(),
        R"(Renders a BRDF on preview objects, as `microbrdf render`; returns the image.

brdf: a Brdf, or a list (one per object). scene: 'cylinders' (Dong Fig. 10) | 'plate' |
'sphere' | 'vase' | 'obj' (with obj=path) | 'furnace_sphere'. size (or width, height): pixels.
spp: samples per pixel. wavelengths: hero wavelengths per path. seed: same seed, same image,
any thread count. mis: 'mis' | 'brdf' | 'light'. sampler: 'sobol' (Owen-scrambled Sobol'
points, stratified per pixel; lower noise) | 'independent' (plain Monte Carlo).
direct: the direct-light estimator (with mis='mis'): 'mis' (one light and one BRDF sample,
power heuristic) | 'ris' (resampled importance sampling: ris_brdf_candidates BRDF-sampled and
ris_light_candidates light-sampled directions, one chosen by an unshadowed estimate of its
light, one shadow ray; unbiased, lower noise at equal time for glossy metals under detailed
maps; docs/render.md, "Resampled direct light").
Lights: envmap=path (.exr/.hdr, equirectangular) with env_scale, env_rotation (rad);
white_env=True; point=[((x, y, z), (r, g, b)) intensity W/sr]; sphere_light=[((x, y, z), radius,
(r, g, b))]; disk_light=[((x, y, z), (nx, ny, nz), radius, (r, g, b))] (radiance). No light:
a white sky (the plate: Dong's disk light).
brushing: 'linear' | 'rotational'; brush_angle (rad).
variants: further BRDFs (each a Brdf or a list per object) rendered along the same paths as
`brdf` (shared camera rays, light samples and shadow rays; each direction drawn by one of their
samplers, shares variant_weights, default equal): each image is an unbiased render of its own
BRDF, and their noise is correlated, so differences between them are far cleaner than between
separate renders (direct light by MIS; docs/render.md, "Variants"). Then a list of images is
returned, `brdf`'s first.
light_sets: further lights for `brdf` along the same paths, a list of dicts with the keys
envmap, env_scale, env_rotation, white_env, point (as above; no area lights): each set has its
own light samples and shadow rays, the paths and BRDF samples are shared, so the same object
under two maps costs far less than two renders (direct light by MIS; docs/render.md, "Light
sets"). A set gets no default light. Then a list is returned: what the lights above give (an
image, or with variants a list of images), then `brdf`'s image under each further set.
Returns linear sRGB radiance, float32 (height, width, 3), row 0 at the top: a view on the
renderer's buffer (no copy). Runs without the GIL; progress(fraction) is called from the
calling thread; Ctrl-C is honoured when the image is finished.)");

  m.def("predict", &predict_run, py::arg("inputs"), py::arg("out_dir"), py::arg("metal") = "Fe",
        py::arg("filter_sigma") = 1e-6, py::arg("resolution") = 1025, py::arg("kirchhoff") = false,
        py::arg("wavelength") = 555e-9, py::arg("patch") = py::make_tuple(70e-6, 53e-6),
        py::arg("theta_i") = std::vector<double>{}, py::arg("envmap") = py::none(),
        py::arg("envmap_scale") = 1.0, py::arg("render_width") = 256, py::arg("spp") = 32,
        py::arg("no_render") = false, py::arg("renders") = "all", py::arg("strips") = py::none(),
        py::arg("texel") = 53e-6, py::arg("texture_size") = 128, py::arg("seed") = 1,
        py::arg("threads") = 0, py::arg("level") = "plane", py::arg("spacing") = py::none(),
        py::arg("render_ndf") = "filtered", py::arg("sweep_resolution") = 257,
        py::arg("progress") = py::none(), py::arg("integration") = "midpoint",
        py::arg("supersample") = 0, py::arg("window") = "hann", py::arg("theory") = "auto",
        R"(The whole pipeline, as `microbrdf predict`: scans -> NDFs -> fits -> BRDF slices ->
renders -> out_dir/report.html and summary.json. Returns the summary (a dict, SI units).

inputs: a path (or glob, directory, @manifest) or a list. metal: optical constants of the BRDFs.
filter_sigma (m, or 'auto': the sigma nearest D_K, on sweep_resolution tables), render_ndf
('naive' | 'filtered' | 'kirchhoff': the NDF of the geometric BRDF), theory ('auto' | 'geometric' |
'kirchhoff' | 'rayleigh-rice': the scattering theory of the predicted BRDF's slices and renders;
'auto' picks the valid one from the scans' regime and says why in summary['regime']['theory']),
resolution (N), kirchhoff (also D_K), wavelength (m), patch ((dx, dy) m),
theta_i (radians, the slices' angles of incidence), envmap, envmap_scale, render_width (pixels),
spp, no_render, renders ('all': the measured NDF and every model, strip, studio renders and
swatch | 'measured': the measured NDF's three scenes only | 'none'), strips=(along, across)
exemplar scans for the texture, texel (m),
texture_size, seed, threads, level, spacing. progress: optional callable(str) receiving the
progress lines. integration, supersample, window: D_K's rule ('midpoint' | 'exact'), node
supersampling (0 = automatic, odd 1..15) and tile apodisation ('none' | 'hann' | 'gauss'), as
for ndf(method='kirchhoff') and the CLI's --dk-integration, --dk-supersample, --window. Nothing is left in out_dir when it fails; Ctrl-C interrupts between stages.)");
}

}  // namespace microbrdf::python
