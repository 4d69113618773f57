// predict: renderer-ready materials of the fits (Mitsuba 3 and pbrt-v4 rough conductors, the
// nearest GGX of each fitted NDF with the run's optical constants; a glTF 2.0 .glb of each fit,
// docs/gltf.md), written into export/ of the output folder; the report links them. The tabulated
// (measured) BRDF as an RGL .bsdf table is left to `microbrdf export bsdf` (minutes for a fine
// anisotropic table): the summary gives the command.
#include <filesystem>

#include "microbrdf/fit.hpp"
#include "microbrdf/gltf_export.hpp"
#include "microbrdf/material_spec.hpp"
#include "microbrdf/scene_export.hpp"
#include "report/predict_stages.hpp"

namespace microbrdf::report {
namespace {

// The material as command-line flags ("--metal Cu", "--n 0.2 --k 3"), from the vocabulary.
std::string material_flags(const MaterialSpec& m) {
  const nlohmann::json keys = m.to_json();
  std::string f;
  for (const auto& [key, value] : keys.items()) {
    if (!f.empty()) f += ' ';
    f += key_name(key, KeyStyle::Cli);
    f += ' ';
    const std::string v = value.is_string() ? value.get<std::string>() : value.dump();
    if (v.find_first_of(" ,#") == std::string::npos) {
      f += v;
    } else {
      f += '\'';
      f += v;
      f += '\'';
    }
  }
  return f;
}

/// The analytic BRDF of a fit (its parameters in the model's own convention).
BrdfSpec fit_spec(const FitResult& r) {
  BrdfSpec spec;
  spec.kind = BrdfSpec::Kind::Analytic;
  spec.model_given = true;
  spec.model = ndf_spec(r.model, r.params);
  return spec;
}

}  // namespace

nlohmann::json write_glb(const Context& c, const BrdfSpec& spec, const std::string& rel,
                         double uv_scale) {
  std::filesystem::create_directories(c.path("export"));
  const GltfMaterial m = gltf_material(spec, c.opt.material);
  GltfExportOptions go;
  go.uv_scale = uv_scale;
  write_gltf(m, c.path(rel), go);
  return {{"file", rel}, {"warnings", m.warnings}};
}

nlohmann::json stage_exports(const Context& c, const std::vector<FitResult>& fits) {
  const auto& o = c.opt;
  const OpticalConstants constants = optical_constants(o.material);
  nlohmann::json list = nlohmann::json::array();
  SceneExportOptions so;  // a constant white emitter: no copy of the environment map
  for (const auto& r : fits) {
    const std::string& model = r.model;
    c.log("exports: " + model + " fit as Mitsuba 3 and pbrt-v4 materials");
    const RoughConductor m = nearest_rough_conductor(*fitted_distribution(r), constants);
    nlohmann::json e = {
        {"model", model}, {"alpha_u", m.alpha_u}, {"alpha_v", m.alpha_v}, {"notes", m.notes}};
    for (const char* kind : {"mitsuba", "pbrt"}) {
      const std::string rel = std::string("export/") + kind + "_" + model;
      const auto files = std::string(kind) == "mitsuba" ? export_mitsuba(m, c.path(rel), so)
                                                        : export_pbrt(m, c.path(rel), so);
      nlohmann::json paths = nlohmann::json::array();
      for (const auto& f : files) paths.push_back(rel + "/" + f);
      e[kind] = std::move(paths);
    }
    c.log("exports: " + model + " fit as glTF 2.0");
    e["gltf"] = write_glb(c, fit_spec(r), "export/gltf_" + model + ".glb", 1);
    list.push_back(std::move(e));
  }
  return {{"materials", std::move(list)},
          {"bsdf_command", "microbrdf export bsdf --ndf ndf_filtered.npy " +
                               material_flags(o.material) + " -o measured.bsdf"}};
}

}  // namespace microbrdf::report
