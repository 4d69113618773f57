// predict stage 5b: the comparison strip. The cylinder pair of stage 5 rendered again with each
// fitted NDF (ellipsoid, Beckmann, GGX) and D_K (with --kirchhoff), same lights, exposure, size,
// samples and seed; each against the measured-NDF render: SSIM on the displayed luminance
// (core/image_metrics.hpp, Wang et al. 2004), RMS relative error of the linear luminance, and
// a false-colour difference image. The measured NDF is rendered once more with the next seed:
// the two measured renders differ by Monte Carlo noise only, which gives the noise of one image.
#include <algorithm>
#include <cmath>

#include "core/image_metrics.hpp"
#include "microbrdf/image.hpp"
#include "microbrdf/spectrum.hpp"
#include "report/predict_stages.hpp"

namespace microbrdf::report {
namespace {

// The luminance an 8-bit PNG of the render shows (exposure 0, sRGB transfer, clipped).
std::vector<double> displayed(const std::vector<double>& y) {
  std::vector<double> v(y.size());
  for (std::size_t i = 0; i < y.size(); ++i) v[i] = srgb_encode(y[i]);
  return v;
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  const auto k = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

}  // namespace

nlohmann::json stage_compare_renders(const Context& c, const NdfSet& ndfs,
                                     const std::vector<FitResult>& fits,
                                     const std::shared_ptr<const Fresnel>& fresnel,
                                     const std::shared_ptr<const Brdf>& measured,
                                     const RenderImage& reference, nlohmann::json& timing) {
  const auto& o = c.opt;
  const std::vector<NamedBrdf> models = model_brdfs(ndfs, fits, fresnel);
  const RenderLights lights = predict_lights(o);
  RenderScene scene;
  scene.kind = PreviewScene::Cylinders;
  const int w = reference.width, h = reference.height;
  auto render_with = [&](const std::shared_ptr<const Brdf>& brdf, std::uint64_t seed,
                         const std::string& key) {
    c.log("renders: comparison, cylinders with the " + key + " BRDF");
    RenderOptions ro = predict_render_options(o, w, h);
    ro.seed = seed;
    RenderImage img = render(scene, {std::make_shared<UniformSvbrdf>(brdf)}, lights, ro);
    timing["render_compare_" + key + "_s"] = img.seconds;
    return img;
  };

  const std::vector<double> ref_y = detail::luminance(reference.rgb);
  const std::vector<double> ref_d = displayed(ref_y);
  const auto wz = static_cast<std::size_t>(w), hz = static_cast<std::size_t>(h);

  // Noise: the measured NDF again with the next seed. Var(A - B) = 2 Var(noise) for independent
  // renders, so one image's noise is their RMS relative difference / sqrt(2).
  const RenderImage again = render_with(measured, o.seed + 1, "measured_seed2");
  const std::vector<double> again_y = detail::luminance(again.rgb);
  nlohmann::json out = {{"scene", "cylinders"},
                        {"reference", "img/render_cylinders.png"},
                        {"reference_model", "measured"},
                        {"width", w},
                        {"height", h},
                        {"spp", o.render_spp},
                        {"seed", o.seed},
                        {"noise",
                         {{"second_seed", o.seed + 1},
                          {"rms_relative", detail::rms_relative(again_y, ref_y) / std::sqrt(2.0)},
                          {"ssim_two_seeds", detail::ssim(displayed(again_y), ref_d, wz, hz)}}}};

  // Every model's render, then one difference scale for all (so the images compare): the
  // 99.5th percentile of |Y_model - Y_measured| over every model, in units of the measured
  // render's 99th-percentile luminance.
  std::vector<std::vector<double> > diffs, ys;
  std::vector<RenderImage> imgs;
  for (const auto& m : models) {
    imgs.push_back(render_with(m.brdf, o.seed, m.key));
    const auto& y = ys.emplace_back(detail::luminance(imgs.back().rgb));
    std::vector<double> dlt(y.size());
    for (std::size_t i = 0; i < y.size(); ++i) dlt[i] = std::fabs(y[i] - ref_y[i]);
    diffs.push_back(std::move(dlt));
  }
  const double bright = std::max(quantile(ref_y, 0.99), 1e-12);
  double top = 0;
  for (const auto& dlt : diffs) top = std::max(top, quantile(dlt, 0.995) / bright);
  if (!(top > 0)) top = 1;  // every difference zero: any scale shows black
  out["difference_scale"] = {{"max", top},
                             {"unit", "measured render's 99th-percentile luminance"},
                             {"reference_luminance", bright}};

  auto write_difference = [&](const std::vector<double>& dlt, const std::string& file) {
    RgbImage di(wz, hz);
    for (std::size_t i = 0; i < dlt.size(); ++i) {
      std::uint8_t rgb[3];
      false_colour(std::clamp(dlt[i] / bright / top, 0.0, 1.0), rgb);
      di.set(i % wz, i / wz, rgb[0], rgb[1], rgb[2]);
    }
    write_png(c.path(file), di);
  };
  // The noise alone on the same scale: |second seed - first seed| (sqrt(2) x one image's noise).
  std::vector<double> noise_diff(ref_y.size());
  for (std::size_t i = 0; i < ref_y.size(); ++i) noise_diff[i] = std::fabs(again_y[i] - ref_y[i]);
  write_difference(noise_diff, "img/compare_measured_seed2_difference.png");
  out["noise"]["difference_image"] = "img/compare_measured_seed2_difference.png";

  nlohmann::json list = nlohmann::json::array();
  for (std::size_t k = 0; k < models.size(); ++k) {
    const auto& m = models[k];
    const std::string image = "img/compare_" + m.key + ".png";
    const std::string diff = "img/compare_" + m.key + "_difference.png";
    write_render_png(imgs[k], c.path(image), 0);
    write_difference(diffs[k], diff);
    const auto& y = ys[k];
    list.push_back({{"model", m.key},
                    {"label", m.label},
                    {"material", m.brdf->describe()},
                    {"image", image},
                    {"difference_image", diff},
                    {"ssim", detail::ssim(displayed(y), ref_d, wz, hz)},
                    {"rms_relative", detail::rms_relative(y, ref_y)}});
  }
  out["models"] = std::move(list);
  return out;
}

}  // namespace microbrdf::report
