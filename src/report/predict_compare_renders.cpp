// predict stage 5b: the comparison strip. Each scene of stage 5 (the cylinder pair and the sphere
// under the environment map, the plate under a small light) with each fitted NDF (ellipsoid,
// Beckmann, GGX) and D_K (with --kirchhoff), rendered by stage 5 along the same paths as its
// measured-NDF render (render_variants: same lights, exposure, size, samples and seed, and
// correlated noise); each against that render: SSIM on the displayed luminance
// (core/image_metrics.hpp, Wang et al. 2004), RMS relative error of the linear luminance, and a
// false-colour difference image. The render noise comes with the measured-NDF render itself (the
// two halves of its samples kept apart, see render_split): no extra render.
#include <algorithm>
#include <cmath>
#include <exception>

#include "core/image_metrics.hpp"
#include "microbrdf/image.hpp"
#include "microbrdf/spectrum.hpp"
#include "microbrdf/threads.hpp"
#include "report/predict_stages.hpp"

namespace microbrdf::report {
namespace {

// Standard deviation (pixels) of the Gaussian that smooths the difference images and the
// "smoothed" RMS error.
constexpr double kSmoothPx = 2.0;

// The luminance an 8-bit PNG of the render shows (exposure, sRGB transfer, clipped).
std::vector<double> displayed(const std::vector<double>& y, double exposure_stops) {
  const double k = std::exp2(exposure_stops);
  std::vector<double> v(y.size());
  for (std::size_t i = 0; i < y.size(); ++i) v[i] = srgb_encode(k * y[i]);
  return v;
}

// The image smoothed by a Gaussian of `sigma` pixels (separable, 3 sigma wide, weights
// renormalised at the borders): pixel noise falls by about 2 sqrt(pi) sigma (7x at 2 px) while
// the models' differences, highlights many pixels wide, stay.
std::vector<double> smoothed(const std::vector<double>& v, std::size_t w, std::size_t h,
                             double sigma) {
  const int r = static_cast<int>(std::ceil(3 * sigma));
  std::vector<double> g(2 * r + 1);
  for (int i = -r; i <= r; ++i) g[i + r] = std::exp(-0.5 * i * i / (sigma * sigma));
  auto pass = [&](const std::vector<double>& in, bool along_x) {
    std::vector<double> out(in.size());
    const auto n = static_cast<std::ptrdiff_t>(along_x ? w : h);
    for (std::size_t y = 0; y < h; ++y)
      for (std::size_t x = 0; x < w; ++x) {
        const auto at = static_cast<std::ptrdiff_t>(along_x ? x : y);
        double sum = 0, wsum = 0;
        for (int d = -r; d <= r; ++d) {
          const std::ptrdiff_t q = at + d;
          if (q < 0 || q >= n) continue;
          const std::size_t i =
              along_x ? y * w + static_cast<std::size_t>(q) : static_cast<std::size_t>(q) * w + x;
          sum += g[d + r] * in[i];
          wsum += g[d + r];
        }
        out[y * w + x] = sum / wsum;
      }
    return out;
  };
  return pass(pass(v, true), false);
}

// Half the size (2 x 2 pixel means of the linear radiance): what the report shows in the strip,
// a quarter of the bytes of the full render (whose PNG is linked beside it).
RenderImage half_size(const RenderImage& img) {
  RenderImage s;
  s.width = img.width / 2;
  s.height = img.height / 2;
  s.rgb.assign(static_cast<std::size_t>(s.width) * s.height * 3, 0.f);
  const auto w = static_cast<std::size_t>(img.width);
  for (std::size_t y = 0; y < static_cast<std::size_t>(s.height); ++y)
    for (std::size_t x = 0; x < static_cast<std::size_t>(s.width); ++x)
      for (std::size_t ch = 0; ch < 3; ++ch) {
        const auto at = [&](std::size_t yy, std::size_t xx) {
          return img.rgb[(yy * w + xx) * 3 + ch];
        };
        s.rgb[(y * s.width + x) * 3 + ch] =
            0.25f * (at(2 * y, 2 * x) + at(2 * y, 2 * x + 1) + at(2 * y + 1, 2 * x) +
                     at(2 * y + 1, 2 * x + 1));
      }
  return s;
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  const auto k = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

// One scene's strip; `prefix` ("" for the cylinder pair, whose file names predate the other
// scenes, else "<scene>_") goes into file names.
nlohmann::json compare_scene(const Context& c, const std::vector<NamedBrdf>& models,
                             const ReferenceRender& ref) {
  const auto& o = c.opt;
  const std::string& sc = ref.scene.name;
  const std::string prefix = sc == "cylinders" ? "" : sc + "_";
  const int w = ref.image.width, h = ref.image.height;
  const double ev = ref.exposure_stops;
  if (ref.model_images.size() != models.size())
    throw std::logic_error("comparison strip: the reference render has no model images");

  const std::vector<double> ref_y = detail::luminance(ref.image.rgb);
  const std::vector<double> ref_d = displayed(ref_y, ev);
  const auto wz = static_cast<std::size_t>(w), hz = static_cast<std::size_t>(h);

  // Noise: stage_render kept the two halves of the reference's samples apart and left one
  // realisation r of the reference's own noise (variance sigma^2 per pixel; render_split). Two
  // independent renders would differ by sqrt(2) r: that is the "noise only" row the models are
  // read against, and the noise of one image is RMS(r) / RMS(reference).
  const std::vector<double>& r = ref.noise_luminance;
  if (r.size() != ref_y.size())
    throw std::logic_error("comparison strip: the reference render has no noise estimate");
  std::vector<double> again_y(ref_y.size());
  for (std::size_t i = 0; i < ref_y.size(); ++i) again_y[i] = ref_y[i] + std::sqrt(2.0) * r[i];
  const std::vector<double> ref_s = smoothed(ref_y, wz, hz, kSmoothPx);
  const std::vector<double> again_s = smoothed(again_y, wz, hz, kSmoothPx);
  nlohmann::json out = {
      {"scene", sc},
      {"lights", ref.scene.lights_text},
      {"reference", ref.file},
      {"reference_model", "measured"},
      {"width", w},
      {"height", h},
      {"spp", o.render_spp},
      {"seed", o.seed},
      {"exposure_stops", ev},
      {"smoothing_sigma_px", kSmoothPx},
      {"noise",
       {{"method", o.render_spp >= 2 ? "halves" : "second_render"},
        {"second_seed", ref.noise_seed},
        {"rms_relative", detail::rms_relative(again_y, ref_y) / std::sqrt(2.0)},
        {"rms_relative_smoothed", detail::rms_relative(again_s, ref_s) / std::sqrt(2.0)},
        {"ssim_two_seeds", detail::ssim(displayed(again_y, ev), ref_d, wz, hz)}}}};

  // Every model's render, then one difference scale for all (so the images compare): the
  // 99.5th percentile of |Y_model - Y_measured| (both smoothed) over every model, in units of the
  // measured render's 99th-percentile luminance.
  std::vector<std::vector<double> > diffs, ys, yss;
  const std::vector<RenderImage>& imgs = ref.model_images;
  for (const auto& img : imgs) {
    const auto& y = ys.emplace_back(detail::luminance(img.rgb));
    const auto& ysm = yss.emplace_back(smoothed(y, wz, hz, kSmoothPx));
    std::vector<double> dlt(y.size());
    for (std::size_t i = 0; i < y.size(); ++i) dlt[i] = std::fabs(ysm[i] - ref_s[i]);
    diffs.push_back(std::move(dlt));
  }
  const double bright = std::max(quantile(ref_y, 0.99), 1e-12);
  double top = 0;
  for (const auto& dlt : diffs) top = std::max(top, quantile(dlt, 0.995) / bright);
  if (!(top > 0)) top = 1;  // every difference zero: any scale shows black
  out["difference_scale"] = {{"max", top},
                             {"unit", "measured render's 99th-percentile luminance"},
                             {"reference_luminance", bright}};

  auto write_difference = [&](const std::vector<double>& dlt, const std::string& file,
                              double full_scale) {
    RgbImage di(wz, hz);
    for (std::size_t i = 0; i < dlt.size(); ++i) {
      std::uint8_t rgb[3];
      false_colour(std::clamp(dlt[i] / bright / full_scale, 0.0, 1.0), rgb);
      di.set(i % wz, i / wz, rgb[0], rgb[1], rgb[2]);
    }
    write_png(c.path(file), di);
  };
  // The noise alone on the same scale and smoothing: what two independent renders differ by
  // (sqrt(2) x one image's noise).
  std::vector<double> noise_diff(ref_y.size());
  for (std::size_t i = 0; i < ref_y.size(); ++i) noise_diff[i] = std::fabs(again_s[i] - ref_s[i]);
  const std::string noise_file = "img/compare_" + prefix + "measured_noise_difference.png";
  write_difference(noise_diff, noise_file, top);
  out["noise"]["difference_image"] = noise_file;
  // Renders of 384 px and more: the strip shows half-size copies (same exposure).
  const bool thumbs = w >= 384 && h >= 384;
  auto thumbnail = [&](const RenderImage& img, const std::string& file) {
    write_render_png(half_size(img), c.path(file), ev);
    return file;
  };
  if (thumbs)
    out["reference_thumbnail"] =
        thumbnail(ref.image, "img/compare_" + prefix + "measured_half.png");

  nlohmann::json list = nlohmann::json::array();
  for (std::size_t k = 0; k < models.size(); ++k) {
    const auto& m = models[k];
    const std::string image = "img/compare_" + prefix + m.key + ".png";
    const std::string diff = "img/compare_" + prefix + m.key + "_difference.png";
    write_render_png(imgs[k], c.path(image), ev);
    write_difference(diffs[k], diff, top);
    const auto& y = ys[k];
    nlohmann::json entry = {{"model", m.key},
                            {"label", m.label},
                            {"material", m.brdf->describe()},
                            {"image", image},
                            {"difference_image", diff},
                            {"ssim", detail::ssim(displayed(y, ev), ref_d, wz, hz)},
                            {"rms_relative", detail::rms_relative(y, ref_y)},
                            {"rms_relative_smoothed", detail::rms_relative(yss[k], ref_s)}};
    if (thumbs)
      entry["thumbnail"] = thumbnail(imgs[k], "img/compare_" + prefix + m.key + "_half.png");
    list.push_back(std::move(entry));
  }
  out["models"] = std::move(list);
  // Multiple against single scattering on the same NDF: the light the single-scattering BRDF
  // drops. The single form is the "geometric" model, or the reference itself when the run's
  // theory is geometric. Its own scale (same rule, this image alone): on the strip's scale, which
  // the largest model-vs-reference difference sets, a few per cent of added light is invisible.
  std::size_t ms = models.size(), single = models.size();
  for (std::size_t k = 0; k < models.size(); ++k) {
    if (models[k].key == "multiple_scattering") ms = k;
    if (models[k].key == "geometric") single = k;
  }
  if (ms < models.size()) {
    const std::vector<double>& s_s = single < models.size() ? yss[single] : ref_s;
    const std::vector<double>& s_y = single < models.size() ? ys[single] : ref_y;
    std::vector<double> dlt(s_s.size());
    double sum_ms = 0, sum_single = 0;
    for (std::size_t i = 0; i < dlt.size(); ++i) {
      dlt[i] = std::fabs(yss[ms][i] - s_s[i]);
      sum_ms += ys[ms][i];
      sum_single += s_y[i];
    }
    const std::string file = "img/compare_" + prefix + "ms_vs_single_difference.png";
    // Not below the noise of two renders (noise_diff): where multiple scattering adds next to
    // nothing, its image must not show render noise at full colour.
    double ms_top = std::max(quantile(dlt, 0.995), quantile(noise_diff, 0.995)) / bright;
    if (!(ms_top > 0)) ms_top = top;
    write_difference(dlt, file, ms_top);
    out["multiple_scattering"] = {
        {"single", single < models.size() ? "geometric" : "measured"},
        {"difference_image", file},
        {"difference_scale",
         {{"max", ms_top},
          {"unit", "measured render's 99th-percentile luminance"},
          {"reference_luminance", bright}}},
        {"mean_luminance_ratio", sum_single > 0 ? sum_ms / sum_single : 1.0},
        {"rms_relative_smoothed", detail::rms_relative(yss[ms], s_s)}};
  }
  return out;
}

}  // namespace

nlohmann::json stage_compare_renders(const Context& c, const std::vector<NamedBrdf>& models,
                                     const std::vector<ReferenceRender>& references) {
  // The scenes side by side on the run's threads (each writes its own files; the results keep
  // the scenes' order). An exception in one is rethrown here, the first in scene order.
  const auto n = static_cast<int>(references.size());
  std::vector<nlohmann::json> per_scene(references.size());
  std::vector<std::exception_ptr> failed(references.size());
#pragma omp parallel for schedule(dynamic, 1) \
    num_threads(std::max(1, std::min(n, resolve_thread_count(c.opt.threads))))
  for (int i = 0; i < n; ++i) {
    try {
      per_scene[i] = compare_scene(c, models, references[i]);
    } catch (...) {
      failed[i] = std::current_exception();
    }
  }
  for (const auto& e : failed)
    if (e) std::rethrow_exception(e);
  nlohmann::json scenes = nlohmann::json::array();
  for (auto& s : per_scene) scenes.push_back(std::move(s));
  // The cylinder pair's keys at the top level (as before the other scenes joined), every scene
  // in "scenes".
  nlohmann::json out = nlohmann::json::object();
  for (const auto& s : scenes)
    if (s["scene"] == "cylinders") out = s;
  out["scenes"] = std::move(scenes);
  return out;
}

}  // namespace microbrdf::report
