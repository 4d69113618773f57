// Mitsuba 3 / pbrt-v4 material and scene files (include/microbrdf/scene_export.hpp).
#include "microbrdf/scene_export.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>

#include "export/format_strings.hpp"
#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/fit.hpp"
#include "microbrdf/io.hpp"

namespace microbrdf {
namespace {

namespace fs = std::filesystem;

void ensure_dir(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) throw FileError(dir, "cannot create the output directory");
}

using detail::pbrt_comment;
using detail::pbrt_string;
using detail::xml_attribute;
using detail::xml_comment;

// The file name of the environment map as the scene names it, checked before anything is
// written (an XML attribute cannot hold every file name).
std::string envmap_name(const SceneExportOptions& o) {
  if (o.envmap.empty()) return "";
  const std::string name = fs::path(o.envmap).filename().string();
  (void)xml_attribute(name, o.envmap);
  return name;
}

std::string mitsuba_scene(const std::string& bsdf_xml, const std::string& env,
                          const SceneExportOptions& o, const std::vector<std::string>& notes) {
  std::string s = "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n";
  s += xml_comment("Written by microbrdf: the material on a unit sphere.") + "\n";
  for (const auto& n : notes) s += xml_comment(n) + "\n";
  s += "<scene version=\"3.0.0\">\n";
  s += "  <integrator type=\"path\"/>\n";
  s += "  <sensor type=\"perspective\">\n    <float name=\"fov\" value=\"30\"/>\n";
  s += "    <transform name=\"to_world\">\n      <lookat origin=\"0, 0, 5\" target=\"0, 0, 0\" "
       "up=\"0, 1, 0\"/>\n    </transform>\n";
  s += fmt::format(
      "    <sampler type=\"independent\">\n      <integer name=\"sample_count\" "
      "value=\"{}\"/>\n    </sampler>\n",
      o.spp);
  s += fmt::format(
      "    <film type=\"hdrfilm\">\n      <integer name=\"width\" value=\"{}\"/>\n"
      "      <integer name=\"height\" value=\"{}\"/>\n    </film>\n",
      o.width, o.height);
  s += "  </sensor>\n";
  if (env.empty())
    s += "  <emitter type=\"constant\"/>\n";
  else
    s += "  <emitter type=\"envmap\">\n    <string name=\"filename\" value=\"" +
         xml_attribute(env, env) + "\"/>\n  </emitter>\n";
  s += bsdf_xml;
  s += "  <shape type=\"sphere\">\n    <ref id=\"microbrdf\"/>\n  </shape>\n";
  s += "</scene>\n";
  return s;
}

std::string copy_envmap(const std::string& dir, const SceneExportOptions& o) {
  if (o.envmap.empty()) return "";
  const std::string name = envmap_name(o);
  const auto bytes = read_file_bytes(o.envmap, std::uint64_t{1} << 31);
  write_file_atomic((fs::path(dir) / name).string(), bytes);
  return name;
}

// material.xml: the bsdf element alone, in a scene Mitsuba can <include>.
void write_material_xml(const std::string& dir, const std::string& bsdf) {
  write_file_atomic((fs::path(dir) / "material.xml").string(),
                    "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<scene version=\"3.0.0\">\n" +
                        bsdf + "</scene>\n");
}

std::string pbrt_scene(const std::string& material_block, const SceneExportOptions& o,
                       const std::vector<std::string>& notes) {
  std::string s = pbrt_comment("Written by microbrdf: the material on a unit sphere.");
  for (const auto& n : notes) s += pbrt_comment(n);
  s += pbrt_comment(
      "pbrt-v4 environment maps must be equal-area octahedral images; this scene "
      "uses a uniform infinite light.");
  s += "LookAt 0 0 5  0 0 0  0 1 0\n";
  s += "Camera \"perspective\" \"float fov\" [ 30 ]\n";
  s += fmt::format(
      "Film \"rgb\" \"integer xresolution\" [ {} ] \"integer yresolution\" [ {} ]\n"
      "     \"string filename\" \"sphere.exr\"\n",
      o.width, o.height);
  s += fmt::format("Sampler \"zsobol\" \"integer pixelsamples\" [ {} ]\n", o.spp);
  s += "Integrator \"volpath\"\n";
  s += "WorldBegin\n";
  s += "LightSource \"infinite\" \"rgb L\" [ 1 1 1 ]\n";
  s += "AttributeBegin\n";
  s += material_block;
  s += "  Shape \"sphere\" \"float radius\" [ 1 ]\n";
  s += "AttributeEnd\n";
  return s;
}

std::vector<std::string> conductor_spectra(const RoughConductor& m, const std::string& dir) {
  const std::string src = m.constants.name + " (" + m.constants.source + ")";
  write_file_atomic((fs::path(dir) / "eta.spd").string(),
                    spectrum_file_text(m.constants.n, "real index n of " + src));
  write_file_atomic((fs::path(dir) / "k.spd").string(),
                    spectrum_file_text(m.constants.k, "extinction k of " + src));
  return {"eta.spd", "k.spd"};
}

}  // namespace

RoughConductor nearest_rough_conductor(const MicrofacetDistribution& d,
                                       const OpticalConstants& constants) {
  RoughConductor m;
  m.constants = constants;
  double phi = 0;
  // The model says whether GGX holds it exactly; otherwise the nearest GGX is fitted to its table
  // (also for distributions outside the registry, e.g. two-lobe mixtures).
  const NdfModel* model = d.model_name().empty() ? nullptr : &ndf_model(d.model_name());
  const std::vector<double> values = d.model_values();
  NdfExportLobe lobe;
  lobe.exact = false;
  if (model) lobe = model->export_lobe(values);
  if (lobe.exact) {
    m.alpha_u = lobe.alpha_x;
    m.alpha_v = lobe.alpha_y;
    phi = lobe.phi;
  } else {
    FitOptions fo;
    fo.model = "ggx";
    const FitResult r = fit_ndf(tabulate(d, model ? model->name() : "model", 257), fo);
    m.alpha_u = r.params.at("alpha_x");
    m.alpha_v = r.params.at("alpha_y");
    phi = r.phi;
    std::string params;
    for (std::size_t i = 0; model && i < values.size(); ++i) {
      const NdfParam& p = model->params()[i];
      params += fmt::format("{}{} {:.4g}{}", i ? ", " : "", p.name,
                            p.unit == "rad" ? values[i] * 180 / M_PI : values[i],
                            p.unit == "rad" ? " deg" : "");
    }
    m.notes.push_back(fmt::format(
        "nearest GGX of the {} ({}): GGX fit alpha_u {:.4g}, alpha_v {:.4g} (Hellinger "
        "distance {:.3g}){}",
        model ? model->label() + " NDF" : std::string("NDF"), model ? params : d.describe(),
        m.alpha_u, m.alpha_v, r.hellinger, lobe.note.empty() ? "" : "; " + lobe.note));
  }
  // Fold phi into (-pi/2, pi/2]; a quarter turn swaps the axes.
  phi = std::remainder(phi, M_PI);
  if (std::abs(std::abs(phi) - M_PI / 2) < 1e-9) {
    std::swap(m.alpha_u, m.alpha_v);
    phi = 0;
  }
  if (std::abs(phi) > 1e-9 && std::abs(m.alpha_u - m.alpha_v) > 1e-12 * m.alpha_u)
    m.notes.push_back(fmt::format(
        "the alpha_u axis is turned by {:.4g} deg from the surface's u direction; the renderers "
        "align alpha_u with u, so turn the shape's texture coordinates by that angle",
        phi * 180 / M_PI));
  return m;
}

std::string spectrum_file_text(const Spectrum& s, const std::string& comment) {
  std::string out = "# " + comment + "\n# wavelength_nm value\n";
  for (int nm = 360; nm <= 830; nm += 5) out += fmt::format("{} {:.6g}\n", nm, s.at_nm(nm));
  return out;
}

std::vector<std::string> export_mitsuba(const RoughConductor& m, const std::string& dir,
                                        const SceneExportOptions& o) {
  (void)envmap_name(o);
  ensure_dir(dir);
  auto files = conductor_spectra(m, dir);
  std::string bsdf = "  <bsdf type=\"roughconductor\" id=\"microbrdf\">\n";
  for (const auto& n : m.notes) bsdf += "    " + xml_comment(n) + "\n";
  bsdf += "    <string name=\"distribution\" value=\"ggx\"/>\n";
  bsdf += fmt::format("    <float name=\"alpha_u\" value=\"{:.9g}\"/>\n", m.alpha_u);
  bsdf += fmt::format("    <float name=\"alpha_v\" value=\"{:.9g}\"/>\n", m.alpha_v);
  bsdf += "    <spectrum name=\"eta\" filename=\"eta.spd\"/>\n";
  bsdf += "    <spectrum name=\"k\" filename=\"k.spd\"/>\n";
  bsdf += "  </bsdf>\n";
  write_material_xml(dir, bsdf);
  files.push_back("material.xml");
  const std::string env = copy_envmap(dir, o);
  if (!env.empty()) files.push_back(env);
  write_file_atomic((fs::path(dir) / "scene.xml").string(), mitsuba_scene(bsdf, env, o, m.notes));
  files.push_back("scene.xml");
  return files;
}

std::vector<std::string> export_mitsuba_measured(const std::string& bsdf_file,
                                                 const std::string& dir,
                                                 const SceneExportOptions& o,
                                                 const std::vector<std::string>& notes) {
  const std::string filename = xml_attribute(bsdf_file, bsdf_file);
  (void)envmap_name(o);
  ensure_dir(dir);
  std::string bsdf = "  <bsdf type=\"measured\" id=\"microbrdf\">\n";
  for (const auto& n : notes) bsdf += "    " + xml_comment(n) + "\n";
  bsdf += "    <string name=\"filename\" value=\"" + filename + "\"/>\n  </bsdf>\n";
  std::vector<std::string> files;
  write_material_xml(dir, bsdf);
  files.push_back("material.xml");
  const std::string env = copy_envmap(dir, o);
  if (!env.empty()) files.push_back(env);
  write_file_atomic((fs::path(dir) / "scene.xml").string(), mitsuba_scene(bsdf, env, o, notes));
  files.push_back("scene.xml");
  return files;
}

std::vector<std::string> export_pbrt(const RoughConductor& m, const std::string& dir,
                                     const SceneExportOptions& o) {
  ensure_dir(dir);
  auto files = conductor_spectra(m, dir);
  std::string mat;
  for (const auto& n : m.notes) mat += "  " + pbrt_comment(n);
  mat += "  Material \"conductor\"\n";
  mat += "    \"spectrum eta\" \"eta.spd\"\n    \"spectrum k\" \"k.spd\"\n";
  mat += fmt::format("    \"float uroughness\" [ {:.9g} ]\n    \"float vroughness\" [ {:.9g} ]\n",
                     m.alpha_u, m.alpha_v);
  mat += "    \"bool remaproughness\" false\n";
  write_file_atomic((fs::path(dir) / "material.pbrt").string(), mat);
  files.push_back("material.pbrt");
  write_file_atomic((fs::path(dir) / "scene.pbrt").string(), pbrt_scene(mat, o, m.notes));
  files.push_back("scene.pbrt");
  return files;
}

std::vector<std::string> export_pbrt_measured(const std::string& bsdf_file, const std::string& dir,
                                              const SceneExportOptions& o,
                                              const std::vector<std::string>& notes) {
  ensure_dir(dir);
  std::string mat;
  for (const auto& n : notes) mat += "  " + pbrt_comment(n);
  mat += "  Material \"measured\" \"string filename\" " + pbrt_string(bsdf_file) + "\n";
  write_file_atomic((fs::path(dir) / "material.pbrt").string(), mat);
  write_file_atomic((fs::path(dir) / "scene.pbrt").string(), pbrt_scene(mat, o, notes));
  return {"material.pbrt", "scene.pbrt"};
}

}  // namespace microbrdf
