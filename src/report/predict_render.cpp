// predict stage 5: preview renders of the measured BRDF (the microfacet BRDF of the filtered NDF
// and the chosen metal): the cylinder pair of Dong 2015 Fig. 10 (the second cylinder has the
// brushing turned 90 degrees) and a sphere, under the environment map or built-in area lights.
#include <chrono>
#include <cmath>

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
  return ro;
}

nlohmann::json stage_render(const Context& c, const std::shared_ptr<const Brdf>& measured,
                            nlohmann::json& timing, RenderImage* cylinders) {
  const auto& o = c.opt;
  if (!o.render) return {{"skipped", "rendering turned off (--no-render)"}};
  std::vector<std::shared_ptr<const Svbrdf> > mats{std::make_shared<UniformSvbrdf>(measured)};
  const RenderLights lights = predict_lights(o);
  struct Job {
    PreviewScene scene;
    const char* name;
    const char* caption;
    int width, height;
  };
  const int w = o.render_width;
  const Job jobs[] = {
      {PreviewScene::Cylinders, "cylinders",
       "Cylinder pair (Dong 2015 Fig. 10): the same measured BRDF, the brushing direction turned "
       "90 degrees between the two",
       w, w},
      {PreviewScene::Sphere, "sphere",
       "Sphere with the measured BRDF (brushing along the camera's "
       "horizontal)",
       w, w}};
  nlohmann::json out = nlohmann::json::array();
  for (const auto& j : jobs) {
    c.log(std::string("renders: ") + j.name + " " + std::to_string(j.width) + " x " +
          std::to_string(j.height) + ", " + std::to_string(o.render_spp) + " spp");
    RenderScene scene;
    scene.kind = j.scene;
    RenderOptions ro = predict_render_options(o, j.width, j.height);
    const std::string name = j.name;
    ro.progress = [&c, name, last = -1](double f) mutable {
      const int step = static_cast<int>(f * 4);
      if (step != last && step < 4)
        c.log("renders: " + name + " " + std::to_string(step * 25) + "%");
      last = step;
    };
    const RenderImage img = render(scene, mats, lights, ro);
    const std::string file = std::string("img/render_") + j.name + ".png";
    write_render_png(img, c.path(file), 0);
    timing["render_" + name + "_s"] = img.seconds;
    if (cylinders && j.scene == PreviewScene::Cylinders) *cylinders = img;
    timing["render_" + name + "_samples_per_s"] = img.samples_per_second;
    out.push_back({{"scene", j.name},
                   {"caption", j.caption},
                   {"file", file},
                   {"width", img.width},
                   {"height", img.height},
                   {"spp", ro.spp},
                   {"max_depth", ro.max_depth},
                   {"wavelengths_per_path", ro.wavelengths},
                   {"seed", ro.seed},
                   {"rays", img.rays},
                   {"material", measured->describe()},
                   {"lights", predict_lights_description(o)}});
  }
  return out;
}

}  // namespace microbrdf::report
