// mb.brdf(**flags): the microfacet BRDF of Dong 2015 eq. 1 (analytic or tabulated NDF), the
// Kirchhoff BRDF (eq. 8) or a Lambertian, with the material given the way the CLI names it.
#include "brdf_factory.hpp"

#include <pybind11/stl.h>

#include <set>

#include "microbrdf/error.hpp"
#include "microbrdf/kirchhoff_brdf.hpp"
#include "microbrdf/lambertian_brdf.hpp"
#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/ndf_io.hpp"
#include "microbrdf/tabulated_distribution.hpp"

namespace microbrdf::python {
namespace {

const std::set<std::string> kKeys = {"model",   "alpha",       "alpha_x",   "alpha_y", "phi",
                                     "theta_x", "theta_y",     "theta_z",   "ndf",     "kirchhoff",
                                     "metal",   "n",           "k",         "nk_csv",  "r0",
                                     "fresnel", "separable_g", "lambertian"};

TabulatedNdf table_of(const py::handle& obj) {
  if (py::isinstance<TabulatedNdf>(obj)) return obj.cast<const TabulatedNdf&>();
  const std::string p = fspath(obj);
  return read_ndf(p);
}

OpticalConstants material(const py::kwargs& kw) {
  const bool has_metal = kw.contains("metal"), has_nk = kw.contains("n") || kw.contains("k"),
             has_csv = kw.contains("nk_csv"), has_r0 = kw.contains("r0");
  if (has_metal + has_nk + has_csv + has_r0 != 1)
    throw InputError("give exactly one material: metal=, n= and k=, nk_csv= or r0=");
  if (has_metal) return metal(kw["metal"].cast<std::string>());
  if (has_csv) return read_optical_constants_csv(fspath(kw["nk_csv"]));
  if (has_r0) {
    const double r0 = kw["r0"].cast<double>();
    if (!(r0 >= 0 && r0 < 1)) throw InputError("r0 must lie in [0, 1)");
    return from_normal_reflectance(Spectrum::constant(r0), 1.0);
  }
  if (!kw.contains("n") || !kw.contains("k")) throw InputError("n and k go together");
  const double n = kw["n"].cast<double>(), k = kw["k"].cast<double>();
  if (!(n > 0) || !(k >= 0)) throw InputError("n must be > 0 and k >= 0");
  return constant_index(n, k);
}

std::shared_ptr<const Fresnel> fresnel(const py::kwargs& kw) {
  const OpticalConstants mat = material(kw);
  const std::string f = kw.contains("fresnel") ? kw["fresnel"].cast<std::string>() : "exact";
  if (f == "exact") return std::make_shared<ConductorFresnel>(mat);
  if (f == "schlick") return std::make_shared<SchlickFresnel>(mat.normal_reflectance_spectrum());
  throw InputError("fresnel must be 'exact' or 'schlick'");
}

double number(const py::kwargs& kw, const char* key, double fallback) {
  return kw.contains(key) ? kw[key].cast<double>() : fallback;
}

}  // namespace

py::object make_brdf(const py::kwargs& kw) {
  for (auto item : kw)
    if (!kKeys.count(item.first.cast<std::string>()))
      throw InputError("brdf: unknown keyword '" + item.first.cast<std::string>() + "'");
  if (kw.contains("lambertian")) {
    const double a = kw["lambertian"].cast<double>();
    if (!(a >= 0 && a <= 1)) throw InputError("lambertian albedo must lie in [0, 1]");
    return py::cast(std::make_shared<LambertianBrdf>(a));
  }
  auto f = fresnel(kw);
  if (kw.contains("kirchhoff")) {
    std::vector<TabulatedNdf> tables;
    py::object k = kw["kirchhoff"];
    if (py::isinstance<py::list>(k) || py::isinstance<py::tuple>(k))
      for (auto t : k) tables.push_back(table_of(t));
    else
      tables.push_back(table_of(k));
    return py::cast(std::make_shared<KirchhoffBrdf>(std::move(tables), f));
  }
  const bool separable = kw.contains("separable_g") && kw["separable_g"].cast<bool>();
  std::shared_ptr<MicrofacetDistribution> d;
  if (kw.contains("ndf")) {
    for (const char* key :
         {"model", "alpha", "alpha_x", "alpha_y", "phi", "theta_x", "theta_y", "theta_z"})
      if (kw.contains(key))
        throw InputError(std::string("ndf= replaces the analytic model: do not combine it with ") +
                         key + "=");
    d = std::make_shared<TabulatedDistribution>(table_of(kw["ndf"]));
  } else {
    NdfSpec s;
    s.model = kw.contains("model") ? kw["model"].cast<std::string>() : "ggx";
    const double alpha = number(kw, "alpha", 0);
    s.alpha_x = number(kw, "alpha_x", alpha);
    s.alpha_y = number(kw, "alpha_y", alpha > 0 ? alpha : s.alpha_x);
    if (!(s.alpha_x > 0))
      throw InputError("give the roughness: alpha=, or alpha_x= (and alpha_y=)");
    s.phi = number(kw, "phi", 0);
    s.theta_x = number(kw, "theta_x", 0);
    s.theta_y = number(kw, "theta_y", 0);
    s.theta_z = number(kw, "theta_z", 0);
    d = make_distribution(s);
  }
  return py::cast(std::make_shared<MicrofacetBrdf>(d, f, separable));
}

const char* brdf_factory_doc() {
  return R"(A BRDF from the keyword names of the CLI flags (angles in radians).

Microfacet (Dong 2015 eq. 1): model='ggx'|'beckmann'|'ellipsoid' with alpha= (both axes) or
alpha_x=, alpha_y=; phi= (beckmann/ggx: azimuth of the alpha_x axis); theta_x=, theta_y=,
theta_z= (ellipsoid); or ndf=D (a TabulatedNdf or the path of a table) instead of the model.
separable_g=True: G1 G1 (Dong eq. 13) instead of the height-correlated Smith G2.
Kirchhoff (Dong eq. 8): kirchhoff=D_K (a table, a path, or a list of tables at several lambda_q).
Material (exactly one): metal='Au'|'Ag'|'Cu'|'Al'|'Fe'|..., n= and k= (constant complex index),
nk_csv=path ('wavelength_nm,n,k'), r0= (normal-incidence reflectance, eta = 1).
fresnel='exact' (default) | 'schlick'. lambertian=albedo: a Lambertian instead.

Example: mb.brdf(model='ggx', alpha_x=0.1, alpha_y=0.3, metal='Cu'))";
}

}  // namespace microbrdf::python
