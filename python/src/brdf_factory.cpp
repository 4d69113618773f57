// mb.brdf(**keys): the library's one BRDF and material vocabulary (brdf_spec.hpp,
// material_spec.hpp) with Python values. Keywords are the spec keys (the CLI flags with '_');
// numbers are SI and angles radians (a string such as "5deg" keeps its unit); files may be
// str or os.PathLike; ndf= and kirchhoff= also take TabulatedNdf objects held in memory.
#include "brdf_factory.hpp"

#include <pybind11/stl.h>

#include <algorithm>
#include <cstdio>

#include "microbrdf/brdf_spec.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/kirchhoff_brdf.hpp"
#include "microbrdf/material_spec.hpp"
#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/ndf_io.hpp"
#include "microbrdf/tabulated_distribution.hpp"

namespace microbrdf::python {
namespace {

bool is_angle_key(const std::string& k) {
  return k == "phi" || k == "theta_x" || k == "theta_y" || k == "theta_z";
}

/// A TabulatedNdf given in place of a file: remembered, and named by a placeholder in the keys
/// so that the spec checks the combination as for a file.
struct InMemory {
  std::vector<std::shared_ptr<TabulatedNdf>> tables;
  /// The name of the table added last.
  nlohmann::json placeholder() const {
    return "<TabulatedNdf " + std::to_string(tables.size() - 1) + ">";
  }
};

nlohmann::json value_json(const std::string& key, const py::handle& v, InMemory& mem) {
  if (py::isinstance<TabulatedNdf>(v)) {
    mem.tables.push_back(v.cast<std::shared_ptr<TabulatedNdf>>());
    return mem.placeholder();
  }
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>();
  if (is_angle_key(key) && (py::isinstance<py::int_>(v) || py::isinstance<py::float_>(v))) {
    char text[40];  // radians, exactly: the spec reads a bare JSON number as degrees
    std::snprintf(text, sizeof text, "%.17grad", v.cast<double>());
    return text;
  }
  if (py::isinstance<py::int_>(v) || py::isinstance<py::float_>(v)) return v.cast<double>();
  if (is_path(v)) return fspath(v, key);
  if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
    nlohmann::json a = nlohmann::json::array();
    for (auto item : v) a.push_back(value_json(key, item, mem));
    return a;
  }
  throw InputError(key + ": unsupported value of type " +
                   py::str(py::type::handle_of(v).attr("__name__")).cast<std::string>());
}

TabulatedNdf table(const std::string& name, const InMemory& mem) {
  if (name.rfind("<TabulatedNdf ", 0) == 0) return *mem.tables.at(std::stoul(name.substr(14)));
  return read_ndf(name);
}

/// The spec keys of the keywords (BRDF and material vocabulary only); `who` names the caller.
nlohmann::json collect_keys(const py::kwargs& kwargs, InMemory& mem, const std::string& who) {
  const auto& bk = brdf_keys();
  const auto& mk = material_keys();
  nlohmann::json keys = nlohmann::json::object();
  for (auto item : kwargs) {
    const std::string k = item.first.cast<std::string>();
    if (std::find(bk.begin(), bk.end(), k) == bk.end() &&
        std::find(mk.begin(), mk.end(), k) == mk.end())
      throw InputError(who + ": unknown keyword '" + k + "'");
    if (!item.second.is_none()) keys[k] = value_json(k, item.second, mem);
  }
  return keys;
}

}  // namespace

nlohmann::json file_spec_keys(const py::kwargs& kwargs, const std::string& who) {
  InMemory mem;
  nlohmann::json keys = collect_keys(kwargs, mem, who);
  if (!mem.tables.empty())
    throw InputError(who + ": give ndf= and kirchhoff= as paths (save a TabulatedNdf first)");
  return keys;
}

py::object make_brdf(const py::kwargs& kwargs) {
  InMemory mem;
  const nlohmann::json keys = collect_keys(kwargs, mem, "brdf");
  const BrdfSpec spec = parse_brdf(keys, std::nullopt, KeyStyle::Python);
  if (!spec.uses_material() && has_material(keys))
    throw InputError("brdf: " + spec.describe() + " takes no material");
  const MaterialSpec material =
      spec.uses_material() ? parse_material(keys, std::nullopt, KeyStyle::Python) : MaterialSpec{};
  std::shared_ptr<const Brdf> b;
  if (mem.tables.empty()) {
    b = call_released([&] { return make_brdf(spec, material); });
  } else if (spec.kind == BrdfSpec::Kind::Tabulated) {
    // The factory's tabulated kind, with the table from memory instead of a file.
    b = make_microfacet_brdf(std::make_shared<TabulatedDistribution>(table(spec.ndf, mem)),
                             make_fresnel(material), spec);
  } else if (spec.kind == BrdfSpec::Kind::Kirchhoff) {
    std::vector<TabulatedNdf> tables;
    for (const auto& name : spec.kirchhoff) tables.push_back(table(name, mem));
    b = std::make_shared<KirchhoffBrdf>(std::move(tables), make_fresnel(material),
                                        spec.model_given ? make_distribution(spec.model) : nullptr);
  } else {
    throw InputError("brdf: a TabulatedNdf goes with ndf= or kirchhoff= only");
  }
  if (const auto* k = dynamic_cast<const KirchhoffBrdf*>(b.get()); k && k->single_table())
    PyErr_WarnEx(PyExc_UserWarning,
                 "brdf: kirchhoff= is one D_K table, used at every direction although each "
                 "direction's lambda_q = 2 lambda / |wi + wo| differs from its lambda_q; "
                 "mb.ndf(method='kirchhoff') returns a stack over lambda_q by default",
                 1);
  return py::cast(std::const_pointer_cast<Brdf>(b));
}

const char* brdf_factory_doc() {
  return R"(A BRDF from the keys of the CLI's BRDF and material flags (`--alpha-x` -> alpha_x).

Angles in radians (or a string with a unit, "5deg"); files as str or pathlib.Path.
Microfacet (Dong 2015 eq. 1): model='ggx'|'beckmann'|'ellipsoid' with alpha= (both axes) or
alpha_x=, alpha_y=; phi= (beckmann/ggx: azimuth of the alpha_x axis); theta_x=, theta_y=,
theta_z= (ellipsoid); or ndf=D (a TabulatedNdf, or the path of a table) instead of the model;
separable_g=True: G1 G1 (Dong eq. 13) instead of the height-correlated Smith G2;
multiple_scattering=True: adds the light that bounces between microfacets more than once (the
microfacet random walk of Heitz 2016 with the NDF's own Smith Lambda and visible normals; eval is
a Monte Carlo estimate seeded from its arguments, so repeated calls agree; default False; see
docs/multiple_scattering.md).
Kirchhoff (Dong eq. 8): kirchhoff=D_K (a table, a path, or a list of them at several lambda_q);
a model given with it supplies the shadowing G.
Others: sun=s (Sun 2002, s = tau/sigma), sh=path (.shbrdf; l_filter=, filter_width=,
isotropic_average=), lambertian=albedo, mirror=True.
Material (exactly one, for every kind but sh and lambertian): metal='Au'|'Ag'|'Cu'|'Al'|'Fe'|...,
n= and k= (constant complex index), nk_csv=path ('wavelength_nm,n,k'), r0= (normal-incidence
reflectance, eta = 1), color='r,g,b' or '#rrggbb'; fresnel='exact' (default) | 'schlick'.

Example: mb.brdf(model='ggx', alpha_x=0.1, alpha_y=0.3, metal='Cu'))";
}

}  // namespace microbrdf::python
