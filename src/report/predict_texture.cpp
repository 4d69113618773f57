// predict stage 6 (with --strips ALONG ACROSS): per-texel ellipsoid fits of exemplar strips
// scanned along and across the brushing direction, separable synthesis of a parameter texture
// (Dong 2015 section 9), false-colour images of its channels and a render of the textured cylinder
// pair.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "microbrdf/image.hpp"
#include "microbrdf/render.hpp"
#include "microbrdf/texture.hpp"
#include "report/predict_stages.hpp"

namespace microbrdf::report {

namespace {

const char* kChannel[5] = {"alpha_x", "alpha_y", "theta_x", "theta_y", "theta_z"};

/// Mean, std, min, max of one channel over the valid texels (texture.hpp channel_stats).
nlohmann::json channel_json(const ParamTexture& t, int ch) {
  const ChannelStats st = channel_stats(t, ch);
  if (st.count == 0) return {{"valid_texels", 0}};
  return {{"valid_texels", st.count},
          {"mean", st.mean},
          {"std", std::sqrt(std::max(0.0, st.variance))},
          {"min", st.min},
          {"max", st.max}};
}

/// Channel `ch` in false colour over [lo, hi], nearest-neighbour enlarged to >= 192 px.
void channel_png(const ParamTexture& t, int ch, double lo, double hi, const std::string& path) {
  const std::size_t scale =
      std::max<std::size_t>(1, 192 / std::max<std::size_t>(1, std::max(t.nx, t.ny)) + 1);
  RgbImage img(t.nx * scale, t.ny * scale);
  for (std::size_t y = 0; y < img.height; ++y)
    for (std::size_t x = 0; x < img.width; ++x) {
      const std::size_t i = (y / scale) * t.nx + x / scale;
      std::uint8_t c[3] = {128, 128, 128};
      if (t.valid.empty() || t.valid[i]) {
        const double v = t.channel[ch][i];
        false_colour(hi > lo ? std::clamp((v - lo) / (hi - lo), 0.0, 1.0) : 0.5, c);
      }
      img.set(x, y, c[0], c[1], c[2]);
    }
  write_png(path, img);
}

nlohmann::json describe_texture(const Context& c, const ParamTexture& t, const std::string& name) {
  nlohmann::json j = {{"nx", t.nx}, {"ny", t.ny}, {"texel_m", t.texel_m}, {"meta", t.meta}};
  std::size_t invalid = 0;
  for (auto v : t.valid) invalid += v ? 0 : 1;
  j["invalid_texels"] = invalid;
  for (const char* k : {"alpha_zoomed", "alpha_lifted_to_min"})  // fitted texels only
    if (t.meta.contains(k)) j[k] = t.meta.at(k);
  for (int ch = 0; ch < 5; ++ch) {
    auto st = channel_json(t, ch);
    j["channels"][kChannel[ch]] = st;
    if (ch < 2 && st.contains("min")) {
      const std::string file = "img/texture_" + name + "_" + kChannel[ch] + ".png";
      channel_png(t, ch, st["min"].get<double>(), st["max"].get<double>(), c.path(file));
      j["images"][kChannel[ch]] = file;
    }
  }
  return j;
}

}  // namespace

nlohmann::json stage_texture(const Context& c, const std::shared_ptr<const Fresnel>& fresnel,
                             nlohmann::json& timing) {
  const auto& o = c.opt;
  if (o.strips_along.empty()) return {{"skipped", "no --strips given"}};
  TexelFitOptions to;
  to.texel_m = o.texel_m;
  to.filter_sigma_m = o.filter_sigma_m;
  to.ndf_resolution = o.texel_resolution;
  to.threads = o.threads;
  to.leveling = o.leveling;
  c.log("texture: per-texel fits of the strip along the brushing");
  const ParamTexture along = fit_texels(o.strips_along, o.read, to);
  c.log("texture: per-texel fits of the strip across the brushing");
  to.stack_along_y = true;  // the across strip's texels run along y (Dong's 1 x N strip)
  const ParamTexture across = fit_texels(o.strips_across, o.read, to);
  SynthesisOptions so;
  so.size = o.texture_size;
  so.seed = o.seed;
  c.log("texture: synthesis " + std::to_string(so.size) + " x " + std::to_string(so.size));
  auto synth = std::make_shared<ParamTexture>(synthesize_texture(along, across, so));
  write_param_texture(*synth, c.path("texture.exr"));
  // Scene units read as 5 cm of real surface (as the 10 cm plate of Dong Fig. 13, 2 units).
  const double uv_scale = 0.05 / std::max(1e-12, synth->texel_m * static_cast<double>(synth->nx));
  BrdfSpec texture_spec;
  texture_spec.kind = BrdfSpec::Kind::Texture;
  texture_spec.texture = c.path("texture.exr");
  c.log("texture: glTF 2.0 with its anisotropy texture");
  nlohmann::json glb = write_glb(c, texture_spec, "export/texture.glb", uv_scale);
  nlohmann::json out = {{"strips_along", o.strips_along},
                        {"strips_across", o.strips_across},
                        {"texel_m", o.texel_m},
                        {"texel_ndf_resolution", o.texel_resolution},
                        {"size", o.texture_size},
                        {"seed", o.seed},
                        {"file", "texture.exr"},
                        {"gltf", std::move(glb)},
                        {"along", describe_texture(c, along, "along")},
                        {"across", describe_texture(c, across, "across")},
                        {"synthesised", describe_texture(c, *synth, "synthesised")}};
  if (o.render) {
    c.log("texture: render of the textured cylinder pair");
    auto svbrdf = std::make_shared<EllipsoidTextureSvbrdf>(synth, fresnel);
    RenderScene scene;
    scene.kind = PreviewScene::Cylinders;
    scene.uv_scale = uv_scale;
    const RenderOptions ro = predict_render_options(o, o.render_width, o.render_width);
    const RenderImage img = render(scene, {svbrdf}, predict_lights(o), ro);
    write_render_png(img, c.path("img/render_texture.png"), 0);
    timing["render_texture_s"] = img.seconds;
    out["render"] = {{"scene", "cylinders"},
                     {"file", "img/render_texture.png"},
                     {"width", img.width},
                     {"height", img.height},
                     {"spp", ro.spp},
                     {"uv_scale", scene.uv_scale},
                     {"lights", predict_lights_description(o)}};
  }
  return out;
}

}  // namespace microbrdf::report
