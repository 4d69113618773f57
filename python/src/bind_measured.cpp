// Measured BRDFs and renderer-ready files: mb.measured_ndf (Dong 2015 eq. 9 on a goniometer CSV,
// a MERL .binary or an RGL .bsdf), mb.export_bsdf (an RGL .bsdf tensor file of any BRDF) and
// mb.export_gltf (glTF 2.0), the library calls behind `microbrdf measured ndf` and `microbrdf
// export bsdf|gltf` (docs/measured.md, docs/gltf.md).
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "bindings.hpp"
#include "brdf_factory.hpp"
#include "microbrdf/atomic_file.hpp"
#include "microbrdf/brdf_spec.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/export.hpp"
#include "microbrdf/gltf_export.hpp"
#include "microbrdf/material_spec.hpp"
#include "microbrdf/measured_ndf.hpp"
#include "microbrdf/memory_budget.hpp"

namespace microbrdf::python {
namespace {

nlohmann::json material_keys_json(const py::kwargs& kwargs) {
  const auto& mk = material_keys();
  nlohmann::json keys = nlohmann::json::object();
  for (auto item : kwargs) {
    const std::string k = item.first.cast<std::string>();
    if (std::find(mk.begin(), mk.end(), k) == mk.end())
      throw InputError("measured_ndf: unknown keyword '" + k + "'");
    const py::handle v = item.second;
    if (v.is_none()) continue;
    if (py::isinstance<py::bool_>(v))
      throw InputError(key_name(k, KeyStyle::Python) + " takes a number or a string");
    if (py::isinstance<py::int_>(v) || py::isinstance<py::float_>(v))
      keys[k] = v.cast<double>();
    else if (is_path(v))
      keys[k] = fspath(v, k);
    else
      throw InputError(key_name(k, KeyStyle::Python) + " takes a number or a string");
  }
  return keys;
}

py::object measured_ndf(const py::object& path, double theta_d, std::size_t resolution,
                        double wavelength, const std::string& shadowing, double kernel,
                        const py::kwargs& kwargs) {
  const std::string p = fspath(path, "path");
  EffectiveNdfOptions o;
  if (!(theta_d > 0 && theta_d < M_PI)) throw InputError("theta_d must lie in (0, pi) rad");
  if (resolution < 5 || resolution > 8193) throw InputError("resolution must lie in 5..8193");
  check_count("resolution", mul_sat(resolution, resolution), 4 * sizeof(double),
              "the effective NDF's tables");
  if (!(wavelength > 0)) throw InputError("wavelength must be positive (metres)");
  if (shadowing != "none" && shadowing != "smith")
    throw InputError("shadowing must be 'none' or 'smith'");
  // The kernel's range (0 = automatic) is checked by the library, with the CLI's message.
  o.theta_d = theta_d;
  o.resolution = resolution;
  o.wavelength_m = wavelength;
  o.smith = shadowing == "smith";
  o.kernel_sigma = kernel;
  const nlohmann::json keys = material_keys_json(kwargs);
  if (!has_material(keys) && keys.contains("fresnel"))
    throw InputError("measured_ndf: fresnel= needs a material (metal=, n= and k=, ...)");
  const std::shared_ptr<const Fresnel> f =
      has_material(keys) ? make_fresnel(parse_material(keys, std::nullopt, KeyStyle::Python))
                         : std::make_shared<PerfectMirrorFresnel>();
  return py::cast(
      call_released([&] { return std::make_shared<TabulatedNdf>(measured_ndf_file(p, *f, o)); }));
}

py::dict export_bsdf(const py::object& output, const py::object& measured,
                     const py::object& brdf_obj, const py::object& isotropic, std::size_t theta_i,
                     std::size_t phi_i, std::size_t ndf_grid, std::size_t samples,
                     const py::object& wavelengths, const py::object& progress,
                     const py::kwargs& kwargs) {
  const std::string out = fspath(output, "output");
  const int given = int(!measured.is_none()) + int(!brdf_obj.is_none()) + int(kwargs.size() > 0);
  if (given != 1)
    throw InputError(
        "export_bsdf: give exactly one of measured= (a .binary/.bsdf path), brdf= (a Brdf) or "
        "the keywords of mb.brdf (model=, alpha=, ndf=, ..., metal=, ...)");
  std::shared_ptr<const Brdf> b;
  std::string what;
  if (!measured.is_none()) {
    const std::string m = fspath(measured, "measured");
    b = call_released([&] { return std::shared_ptr<const Brdf>(read_measured_brdf(m)); });
    what = std::filesystem::path(m).filename().string();
  } else {
    const py::object o = brdf_obj.is_none() ? make_brdf(kwargs) : brdf_obj;
    if (!py::isinstance<Brdf>(o)) throw InputError("export_bsdf: brdf= must be a microbrdf.Brdf");
    b = o.cast<std::shared_ptr<Brdf>>();
    what = b->describe();
  }
  for (auto [v, name] :
       {std::pair{theta_i, "theta_i"}, {ndf_grid, "ndf_grid"}, {samples, "samples"}})
    if (v < 2 || v > 512) throw InputError(std::string(name) + " must lie in 2..512");
  RglExportOptions o;
  if (py::isinstance<py::int_>(wavelengths)) {
    const auto n = wavelengths.cast<std::size_t>();
    if (n < 2 || n > 512) throw InputError("wavelengths: a count must lie in 2..512");
    o.wavelengths_nm.resize(n);
    for (std::size_t i = 0; i < n; ++i)
      o.wavelengths_nm[i] = 360.0 + 470.0 * double(i) / double(n - 1);
  } else {
    o.wavelengths_nm.clear();
    for (auto w : wavelengths.cast<py::sequence>()) {
      const double m = w.cast<double>();
      if (!(m > 100e-9 && m < 20e-6))
        throw InputError("wavelengths: give metres between 100 nm and 20 um");
      o.wavelengths_nm.push_back(m * 1e9);
    }
    if (o.wavelengths_nm.empty()) throw InputError("wavelengths: none given");
  }
  o.theta_i = theta_i;
  o.phi_i = phi_i;
  o.ndf_theta = o.ndf_phi = ndf_grid;
  o.samples = samples;
  o.description = "microbrdf export of " + what;
  if (isotropic.is_none())
    o.isotropic = call_released([&] { return brdf_is_isotropic(*b); });
  else
    o.isotropic = isotropic.cast<bool>();
  if (!o.isotropic && (phi_i < 3 || phi_i > 512)) throw InputError("phi_i must lie in 3..512");
  // The spectra tensor dominates: one float per incident direction, sample node and wavelength
  // (and three more per node for the luminance, ndf and vndf grids).
  check_count("wavelengths",
              mul_sat(mul_sat(theta_i, o.isotropic ? 1 : phi_i),
                      mul_sat(mul_sat(samples, samples), o.wavelengths_nm.size() + 3)),
              sizeof(float), "the .bsdf tensors");
  o.progress = progress_hook<double>(progress);
  call_released([&] {
    const auto d = export_distribution(b);
    write_rgl_bsdf(*b, *d, o, out);
    return 0;
  });
  py::list wl;
  for (double nm : o.wavelengths_nm) wl.append(nm * 1e-9);
  py::dict r;
  r["output"] = path_text(out);
  r["source"] = text(what);
  r["isotropic"] = o.isotropic;
  r["theta_i"] = o.theta_i;
  r["phi_i"] = o.isotropic ? std::size_t(1) : o.phi_i;
  r["ndf_grid"] = ndf_grid;
  r["samples"] = samples;
  r["wavelengths"] = wl;
  r["bytes"] = static_cast<std::uintmax_t>(std::filesystem::file_size(out));
  return r;
}

py::object export_gltf(const py::object& output, double uv_scale, const py::kwargs& kwargs) {
  const std::string out = fspath(output, "output");
  const nlohmann::json keys = file_spec_keys(kwargs, "export_gltf");
  const BrdfSpec spec = parse_brdf(keys, std::nullopt, KeyStyle::Python);
  if (!spec.uses_material() && has_material(keys))
    throw InputError("export_gltf: " + spec.describe() + " takes no material");
  const MaterialSpec material =
      spec.uses_material() ? parse_material(keys, std::nullopt, KeyStyle::Python) : MaterialSpec{};
  GltfExportOptions o;
  o.uv_scale = uv_scale;
  const auto [m, files] = call_released([&] {
    const GltfMaterial mat = gltf_material(spec, material);
    OutputGroup group;  // the .gltf, .bin and PNGs together, or none
    auto written = write_gltf(mat, out, o);
    group.commit();
    return std::pair{mat, written};
  });
  const GltfAnisotropy g = gltf_anisotropy(m.ggx);
  nlohmann::json j = {
      {"output", out},
      {"files", files},
      {"source", m.describe},
      {"ggx", {{"alpha_x", m.ggx.alpha_x}, {"alpha_y", m.ggx.alpha_y}, {"phi", m.ggx.phi}}},
      {"base_color_linear_srgb", m.base_color},
      {"roughness", g.roughness},
      {"anisotropy_strength", g.strength},
      {"anisotropy_rotation", g.rotation},
      {"warnings", m.warnings}};
  return json_to_py(j);
}

}  // namespace

void bind_measured(py::module_& m) {
  m.def("measured_ndf", &measured_ndf, py::arg("path"), py::kw_only(),
        py::arg("theta_d") = 14.14 * M_PI / 180, py::arg("resolution") = 1025,
        py::arg("wavelength") = 550e-9, py::arg("shadowing") = "none", py::arg("kernel") = 0.0,
        R"(Effective NDF of a measured BRDF (Dong 2015 eq. 9), as `microbrdf measured ndf`.

  D(h) = 4 |wi.n| |wo.n| f(wi, wo) / (F(wi.h) G(wi, wo)),  h = (wi + wo)/|wi + wo|

path: a goniometer point set (.csv: theta_i_deg, phi_i_deg, theta_o_deg, phi_o_deg,
  wavelength_nm, brdf_per_sr), a MERL 100 table (.binary) or an RGL tensor file (.bsdf).
theta_d: angle between wi and wo at which full BRDFs are read, radians (default 14.14 deg,
  Dong's setting).
resolution: table nodes per side (5..8193).
wavelength: metres; full BRDFs are read there, point sets use the rows nearest it.
shadowing: 'none' (G = 1, Dong's assumption) or 'smith' (the Smith G2 of the estimate).
kernel: point sets: std of the Gaussian splat in disk coordinates (~ radians near the pole);
  0 = the median nearest-neighbour distance of the half vectors.
Material keywords (metal=, n= and k=, nk_csv=, r0=, color=, fresnel=) give F; without them
F = 1 and the table is the NDF's shape.

Returns a TabulatedNdf in 1/sr (not renormalised); nodes without data are NaN (unmeasured),
which mb.fit ignores. Raises FileError for a file that does not read, InputError for bad
values.)");
  m.def("export_bsdf", &export_bsdf, py::arg("output"), py::arg("measured") = py::none(),
        py::kw_only(), py::arg("brdf") = py::none(), py::arg("isotropic") = py::none(),
        py::arg("theta_i") = 24, py::arg("phi_i") = 17, py::arg("ndf_grid") = 64,
        py::arg("samples") = 32, py::arg("wavelengths") = 25, py::arg("progress") = py::none(),
        R"(Writes a BRDF as an RGL .bsdf tensor file (Dupuy & Jakob 2018), the format of Mitsuba
3's `measured` plugin and pbrt-v4's MeasuredBxDF, as `microbrdf export bsdf` does.

The BRDF is exactly one of: measured= (path of a MERL .binary or RGL .bsdf), brdf= (a Brdf,
e.g. from mb.brdf) or the keywords of mb.brdf (model='ggx', alpha=0.3, n=1.2, k=3.5; ndf=D,
metal='Fe'; ...). The file returns microbrdf's own BRDF exactly at its sample nodes; the grids
follow the BRDF's NDF (microfacet BRDFs) or its lobe.
output: the .bsdf path (written atomically).
isotropic: None = tested on the BRDF; True stores one incident azimuth (phi_i = [0]); False
  stores phi_i incident azimuths over [-pi, pi].
theta_i: incident elevations over [0, 89 deg]; phi_i: incident azimuths (anisotropic);
ndf_grid: ndf/sigma/vndf nodes per axis; samples: spectra/luminance nodes per axis (each
  2..512).
wavelengths: a count spread over 360-830 nm, or a sequence of wavelengths in metres.
progress: optional callable(fraction in [0, 1]), called from the calling thread; the call runs
  without the GIL and Ctrl-C (or an exception from progress) stops it before anything is written.

Defaults: about 3.0 MB isotropic, 50 MB anisotropic; median error of f cos(theta_o) on the lobe
0.07-0.25 % for GGX lobes (docs/measured.md). Returns a dict: output, source, isotropic,
theta_i, phi_i, ndf_grid, samples, wavelengths (metres), bytes.)");
  m.def("export_gltf", &export_gltf, py::arg("output"), py::kw_only(), py::arg("uv_scale") = 1.0,
        R"(Writes a material as glTF 2.0 for real-time viewers, as `microbrdf export gltf` does.

The material is given by the keywords of mb.brdf, the CLI flags with '_' (model='ggx',
alpha_x=0.1, alpha_y=0.3, phi=0.5 (radians), metal='Al'; ndf='table.npy'; texture='tex.exr';
kirchhoff=, sun=, sh=; n= and k=, nk_csv=, r0=, color=, fresnel=); ndf= and kirchhoff= take
paths here. Not lambertian= or mirror= (glTF's metals have no equivalent).
output: a .glb (one binary file) or a .gltf (with <stem>.bin and, for a texture,
  <stem>_roughness.png and <stem>_anisotropy.png beside it), written atomically, all together.
uv_scale: texture repeats per scene unit (KHR_texture_transform), as render's uv_scale.

The file holds a metallic-roughness material (metallic 1, baseColorFactor = the material's
normal-incidence reflectance in linear sRGB, as `brdf color`) with roughness and
KHR_materials_anisotropy from the GGX widths (docs/gltf.md):
  roughness = sqrt(min alpha), anisotropyStrength = sqrt((max - min) / (1 - min)),
  anisotropyRotation = the azimuth of the wider axis,
on a unit sphere (scene 0) and a 2 x 2 plate (scene 1). Beckmann, the ellipsoid, tabulated,
Kirchhoff, Sun and SH BRDFs become their GGX fit.

Returns a dict: output, files, source, ggx {alpha_x, alpha_y, phi (rad)},
base_color_linear_srgb, roughness, anisotropy_strength, anisotropy_rotation (rad), warnings
(what glTF cannot represent: its Schlick Fresnel, its GGX shape and Smith term, with the
errors). Raises InputError for bad keywords, FileError for unreadable inputs.)");
}

}  // namespace microbrdf::python
