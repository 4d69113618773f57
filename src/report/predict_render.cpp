// predict stage 5: preview renders of the measured BRDF (the microfacet BRDF of the filtered NDF
// and the chosen metal): the cylinder pair of Dong 2015 Fig. 10 (the second cylinder has the
// brushing turned 90 degrees) and a sphere under the environment map (or built-in area lights),
// the plate of Dong Fig. 13 under a small light; the cylinders and sphere again under the
// neutral studio map when it lies beside the given map, and a colour swatch (a small sphere in a
// uniform white environment). Each scene's exposure is chosen from its measured-NDF render.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <stdexcept>

#include "core/image_metrics.hpp"
#include "microbrdf/render.hpp"
#include "report/predict_stages.hpp"

namespace microbrdf::report {

std::string predict_lights_description(const PredictOptions& o) {
  return o.envmap_path.empty() ? "built-in: dim uniform sky (0.25) and two disk area lights"
                               : "environment map " + o.envmap_path;
}

RenderLights predict_lights(const PredictOptions& o) {
  RenderLights l;
  if (!o.envmap_path.empty()) {
    l.envmap_path = o.envmap_path;
    l.envmap_scale = o.envmap_scale;
    return l;
  }
  // No map: a dim uniform sky (shows the shape) and two round softboxes high left and right
  // (show the highlights and their anisotropy).
  l.uniform_white_env = true;
  l.envmap_scale = 0.25 * o.envmap_scale;
  l.disks.push_back({Eigen::Vector3d(-4, 4, 3), Eigen::Vector3d(1, -1, -0.75).normalized(), 1.2,
                     Eigen::Vector3d(6, 6, 6)});
  l.disks.push_back({Eigen::Vector3d(4, 3, 2), Eigen::Vector3d(-1, -0.75, -0.5).normalized(), 0.8,
                     Eigen::Vector3d(4, 4, 4)});
  return l;
}

RenderOptions predict_render_options(const PredictOptions& o, int width, int height) {
  RenderOptions ro;
  ro.width = width;
  ro.height = height;
  ro.spp = o.render_spp;
  ro.seed = o.seed;
  ro.threads = o.threads;
  // MIS, not the renderer's default RIS: the comparison strip renders the measured NDF and the
  // models along shared paths, whose light samples serve every variant (RIS serves one), and
  // every render of the report keeps one estimator, so that their noise figures compare. With
  // a tabulated NDF each RIS candidate is a visible-normal draw from tables, which makes a
  // sample about 3x dearer.
  ro.direct = DirectLight::Mis;
  // 4 hero wavelengths (the renderer's default is 8): the report's renders are sized by time
  // (--spp), and 8 cost about 12% more per sample for the measured NDF's tables.
  ro.wavelengths = 4;
  return ro;
}

std::vector<PredictScene> predict_scenes(const PredictOptions& o) {
  std::vector<PredictScene> s(3);
  s[0].name = "cylinders";
  s[0].geometry.kind = PreviewScene::Cylinders;
  s[0].lights = predict_lights(o);
  s[0].lights_text = predict_lights_description(o);
  s[0].caption =
      "Cylinder pair (Dong 2015 Fig. 10): the same measured BRDF, the brushing direction turned "
      "90 degrees between the two";
  s[1].name = "sphere";
  s[1].geometry.kind = PreviewScene::Sphere;
  s[1].lights = s[0].lights;
  s[1].lights_text = s[0].lights_text;
  s[1].caption = "Sphere with the measured BRDF (brushing along the camera's horizontal)";
  s[2].name = "plate";
  s[2].geometry.kind = PreviewScene::Plate;
  // The light of Dong Fig. 13 (dong_plate_light) moved to 6 deg from the camera and shrunk to
  // 3 deg across: its mirror image falls on the plate (0.67 of the half-width left of the
  // centre), so even a narrow lobe shows a highlight, shaped by the lobe.
  {
    RenderLights::Disk d = dong_plate_light();
    const double dist = d.centre.norm(), a = 6 * M_PI / 180, half = 1.5 * M_PI / 180;
    const Eigen::Vector3d dir(-std::sin(a), std::cos(a), 0);
    d.centre = dist * dir;
    d.normal = -dir;
    d.radius = dist * std::tan(half);
    d.rgb_radiance = Eigen::Vector3d::Constant(1 / (std::sin(half) * std::sin(half)));
    s[2].lights.disks.push_back(d);
  }
  s[2].lights_text =
      "one disk light spanning 3 deg, 6 deg left of the camera (irradiance pi on a surface "
      "facing it), nothing else";
  s[2].caption =
      "Flat plate (10 cm, camera 64 cm above, after Dong 2015 Fig. 13) under a small light "
      "whose mirror image falls left of the centre: the highlight is the lobe's shape";
  return s;
}

double auto_exposure_stops(const RenderImage& img) {
  std::vector<double> y = detail::luminance(img.rgb);
  if (y.empty()) return 0;
  const auto k = static_cast<std::size_t>(0.99 * static_cast<double>(y.size() - 1));
  std::nth_element(y.begin(), y.begin() + static_cast<std::ptrdiff_t>(k), y.end());
  if (!(y[k] > 0) || !std::isfinite(y[k])) return 0;
  // Half stops, within +-10 stops: the 99th-percentile luminance shows at (about) full white.
  return std::clamp(std::round(-2 * std::log2(y[k])) / 2, -10.0, 10.0);
}

namespace {

// The neutral studio map beside the given one (the bundled maps share a folder), or "".
std::string studio_beside(const std::string& envmap) {
  if (envmap.empty()) return "";
  const auto p = std::filesystem::path(envmap);
  const auto studio = p.parent_path() / "blender_studio.exr";
  if (p.filename() == "blender_studio.exr" || !std::filesystem::is_regular_file(studio)) return "";
  return studio.string();
}

}  // namespace

// A compared scene's measured-NDF render (the first variant) and the models' renders along the
// same paths, made so that the noise can be told without a second render: the renderer keeps the
// images of the first n0 = floor(N/2) and the last n1 = N - n0 samples apart
// (RenderOptions::half_images) besides the full image, which is the same bit for bit as a render
// without them. With s^2 the variance per sample, the full image has s^2 / N and the halves'
// difference A - B has s^2 (1/n0 + 1/n1), so k (Y_A - Y_B) with k = sqrt(n0 n1) / N is one
// realisation of the image's own noise (k = 1/2 for even N). For the Sobol' sampler the halves
// are two halves of one scrambled sequence, slightly anti-correlated, so this errs high (it is
// the noise two independent half-sample renders would show). At one sample per pixel the image
// is rendered again with seed + 1 and (Y_2 - Y_1) / sqrt 2 is used.
// With `extra_lights`, the first variant under those light sets too, along the same paths
// (render_light_sets; their images after the variants'), the noise of the first image.
std::vector<RenderImage> render_split(
    const PredictScene& scene,
    const std::vector<std::vector<std::shared_ptr<const Svbrdf> > >& variants,
    const RenderOptions& ro, std::vector<double>& noise,
    const std::vector<RenderLights>& extra_lights) {
  const int n = ro.spp;
  std::vector<RenderLights> sets{scene.lights};
  sets.insert(sets.end(), extra_lights.begin(), extra_lights.end());
  if (n < 2) {
    std::vector<RenderImage> a = render_light_sets(scene.geometry, variants, sets, ro);
    RenderOptions ob = ro;
    ob.seed = ro.seed + 1;
    ob.progress = nullptr;
    const RenderImage b = render(scene.geometry, variants.front(), scene.lights, ob);
    const std::vector<double> ya = detail::luminance(a.front().rgb), yb = detail::luminance(b.rgb);
    noise.resize(ya.size());
    // (The second render draws with the first variant's sampler alone: for spp = 1 the noise
    // figure is that of a plain render of the measured NDF.)
    for (std::size_t i = 0; i < ya.size(); ++i) noise[i] = (yb[i] - ya[i]) / std::sqrt(2.0);
    a.front().seconds += b.seconds;
    a.front().rays += b.rays;
    return a;
  }
  RenderOptions o = ro;
  o.half_images = true;
  std::vector<RenderImage> a = render_light_sets(scene.geometry, variants, sets, o);
  const int n0 = n / 2, n1 = n - n0;
  const double k = std::sqrt(static_cast<double>(n0) * n1) / n;
  const std::vector<double> y0 = detail::luminance(a.front().half_rgb[0]),
                            y1 = detail::luminance(a.front().half_rgb[1]);
  noise.resize(y0.size());
  for (std::size_t i = 0; i < y0.size(); ++i) noise[i] = k * (y0[i] - y1[i]);
  for (auto& img : a) img.half_rgb = {};  // the report keeps only the noise
  return a;
}

RenderImage half_size(const RenderImage& img) {
  if (img.width % 2 != 0 || img.height % 2 != 0)
    throw std::invalid_argument("half_size: the width and height must be even");
  RenderImage h = img;
  h.width = img.width / 2;
  h.height = img.height / 2;
  h.rgb.assign(std::size_t(h.width) * h.height * 3, 0.0f);
  h.half_rgb = {};
  for (int y = 0; y < h.height; ++y)
    for (int x = 0; x < h.width; ++x)
      for (int ch = 0; ch < 3; ++ch) {
        double sum = 0;  // (in double: the four floats' mean, rounded once)
        for (int dy = 0; dy < 2; ++dy)
          for (int dx = 0; dx < 2; ++dx)
            sum += img.rgb[((std::size_t(2 * y + dy) * img.width) + 2 * x + dx) * 3 + ch];
        h.rgb[(std::size_t(y) * h.width + x) * 3 + ch] = static_cast<float>(sum / 4);
      }
  return h;
}

nlohmann::json stage_render(const Context& c, const std::shared_ptr<const Brdf>& measured,
                            const std::vector<NamedBrdf>& models, nlohmann::json& timing,
                            std::vector<ReferenceRender>* references) {
  const auto& o = c.opt;
  if (!o.render) return {{"skipped", "rendering turned off (--no-render)"}};
  std::vector<std::shared_ptr<const Svbrdf> > mats{std::make_shared<UniformSvbrdf>(measured)};
  const int w = o.render_width;
  struct Job {
    PredictScene scene;
    std::string key;  ///< file and timing name
    int size;
    int spp;
    bool compared;     ///< a reference of the comparison strip
    bool fixed_zero;   ///< exposure 0 instead of the automatic one (the swatch)
    std::string role;  ///< "scene", "studio", "swatch"
    /// The compared scene whose pass renders this one too, as an extra light set at twice the
    /// size and 1/4 of the samples, then halved (render_light_sets, half_size); "" = its own.
    std::string shared_from = {};
  };
  std::vector<Job> jobs;
  for (const auto& s : predict_scenes(o))
    jobs.push_back({s, s.name, w, o.render_spp, o.render_models, false, "scene"});
  // The material's own colour: the courtyard is warm, a grey metal looks bronze under it.
  if (const std::string studio = studio_beside(o.envmap_path); o.render_models && !studio.empty()) {
    for (int k = 0; k < 2; ++k) {
      PredictScene s = predict_scenes(o)[k];
      const std::string pass = s.name;  // the compared scene whose pass can carry this view
      s.lights = RenderLights{};
      s.lights.envmap_path = studio;
      s.lights.envmap_scale = o.envmap_scale;
      s.lights_text = "neutral studio environment map " + studio;
      s.caption = (k == 0 ? std::string("Cylinder pair") : std::string("Sphere")) +
                  " under the neutral studio map (two softboxes, no colour cast): the "
                  "material's own colour";
      s.name += "_studio";
      // Half size at 4x the samples (half the noise of the compared scenes): context beside
      // them, not compared itself. Rendered along the paths of the same scene under the given
      // map (a second light set at full size, 2 x 2 pixels averaged): an unbiased estimate of
      // the same image with about 7% more noise, for less than half the cost of its own render
      // (docs/render.md, "Light sets").
      const bool shared = w % 2 == 0 && w / 2 >= 16 && o.render_spp <= 65536 / 4;
      jobs.push_back({s, s.name, std::max(16, w / 2), std::min(65536, 4 * o.render_spp), false,
                      false, "studio", shared ? pass : ""});
    }
  }
  if (o.render_models) {
    PredictScene s;
    s.name = "swatch";
    s.geometry.kind = PreviewScene::Sphere;
    s.lights.uniform_white_env = true;
    s.lights_text = "uniform white environment (radiance 1), no other light";
    s.caption =
        "Colour swatch: the measured BRDF on a sphere in a uniform white environment (the "
        "background is white, radiance 1); its colour is the directional albedo's";
    // Small and at >= 64 samples/pixel: a uniform environment converges fast, and a swatch
    // should show a colour, not colour noise from the hero wavelengths.
    const int size = std::clamp(w / 4, 16, 128);
    jobs.push_back({s, "swatch", size, std::max(o.render_spp, 64), false, true, "swatch"});
  }

  nlohmann::json out = nlohmann::json::array();
  std::map<std::string, RenderImage> shared_images;  // key -> image from another job's pass
  for (const auto& j : jobs) {
    c.log("renders: " + j.key + " " + std::to_string(j.size) + " x " + std::to_string(j.size) +
          ", " + std::to_string(j.spp) + " spp" +
          (j.shared_from.empty() ? "" : " (from the " + j.shared_from + " pass)"));
    RenderOptions ro = predict_render_options(o, j.size, j.size);
    ro.spp = j.spp;
    const std::string name = j.key;
    ro.progress = [&c, name, last = -1](double f) mutable {
      const int step = static_cast<int>(f * 4);
      if (step != last && step < 4)
        c.log("renders: " + name + " " + std::to_string(step * 25) + "%");
      last = step;
    };
    std::vector<double> noise;
    std::vector<RenderImage> model_images;
    RenderImage img;
    if (j.compared) {
      // The compared scenes: the measured NDF and every model along the same paths (one pass;
      // the models' differences from the measured render then show the models, not the noise).
      std::vector<std::vector<std::shared_ptr<const Svbrdf> > > variants{mats};
      for (const auto& m : models) variants.push_back({std::make_shared<UniformSvbrdf>(m.brdf)});
      // Half of the directions drawn by the measured NDF's own sampler (its image keeps most of
      // its own noise level), the other half shared by the models; every image stays unbiased
      // (each sampler reaches the whole hemisphere between them) and a model's variance is at
      // most 1 / (its share) times that of its own render (docs/render.md, "Variants").
      if (variants.size() > 1) {
        ro.variant_weights.assign(variants.size(), 1.0);
        ro.variant_weights.front() = static_cast<double>(variants.size() - 1);
      }
      std::vector<const Job*> riders;  // further light sets along these paths
      std::vector<RenderLights> extra;
      for (const auto& r : jobs)
        if (r.shared_from == j.key) {
          riders.push_back(&r);
          extra.push_back(r.scene.lights);
        }
      std::vector<RenderImage> imgs = render_split(j.scene, variants, ro, noise, extra);
      const std::size_t nv = variants.size();
      if (imgs.size() != nv + riders.size())
        throw std::logic_error("predict: a shared pass returned " + std::to_string(imgs.size()) +
                               " images for " + std::to_string(nv + riders.size()));
      for (std::size_t i = 0; i < riders.size(); ++i)  // the measured NDF under each further set
        shared_images[riders[i]->key] = half_size(imgs[nv + i]);
      img = std::move(imgs.front());
      model_images.assign(std::make_move_iterator(imgs.begin() + 1),
                          std::make_move_iterator(imgs.begin() + static_cast<long>(nv)));
    } else if (!j.shared_from.empty()) {
      img = std::move(shared_images.at(j.key));
    } else {
      img = render(j.scene.geometry, mats, j.scene.lights, ro);
    }
    const double exposure = j.fixed_zero ? 0.0 : auto_exposure_stops(img);
    const std::string file = "img/render_" + j.key + ".png";
    write_render_png(img, c.path(file), exposure);
    if (j.shared_from.empty()) {  // (a shared pass's time is its scene's)
      timing["render_" + name + "_s"] = img.seconds;
      timing["render_" + name + "_samples_per_s"] = img.samples_per_second;
    }
    out.push_back({{"scene", j.key},
                   {"geometry", preview_scene_name(j.scene.geometry.kind)},
                   {"role", j.role},
                   {"caption", j.scene.caption},
                   {"file", file},
                   {"width", img.width},
                   {"height", img.height},
                   {"spp", ro.spp},
                   {"max_depth", ro.max_depth},
                   {"wavelengths_per_path", ro.wavelengths},
                   {"seed", ro.seed},
                   {"exposure_stops", exposure},
                   {"rays", img.rays},
                   {"material", measured->describe()},
                   {"lights", j.scene.lights_text}});
    // (spp: per pixel of this image, 4 pixels of the pass; rays: the whole pass's)
    if (!j.shared_from.empty()) out.back()["rendered_in_pass_of"] = j.shared_from;
    if (j.compared) {
      nlohmann::json keys = nlohmann::json::array();
      for (const auto& m : models) keys.push_back(m.key);
      // One pass renders the measured NDF and these models (the comparison strip's images).
      out.back()["shared_paths_with"] = std::move(keys);
    }
    if (references && j.compared) {
      ReferenceRender r;
      r.scene = j.scene;
      r.file = file;
      r.exposure_stops = exposure;
      r.image = std::move(img);
      r.noise_luminance = std::move(noise);
      r.noise_seed = ro.spp >= 2 ? ro.seed : ro.seed + 1;
      r.model_images = std::move(model_images);
      references->push_back(std::move(r));
    }
  }
  return out;
}

}  // namespace microbrdf::report
