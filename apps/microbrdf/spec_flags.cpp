#include "spec_flags.hpp"

#include <algorithm>
#include <cstdio>

#include "microbrdf/error.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/microfacet.hpp"
#include "microbrdf/ndf_io.hpp"
#include "microbrdf/ndf_model.hpp"

namespace microbrdf::cli {

nlohmann::json SpecFlags::keys() const {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [k, v] : text)
    if (!v.empty()) j[k] = v;
  if (!kirchhoff.empty()) j["kirchhoff"] = kirchhoff;
  if (mirror) j["mirror"] = true;
  if (separable_g) j["separable_g"] = true;
  if (multiple_scattering) j["multiple_scattering"] = true;
  if (isotropic_average) j["isotropic_average"] = true;
  return j;
}

void add_material_flags(CLI::App* c, SpecFlags& f, const std::string& default_note) {
  std::string names;
  for (const auto& n : metal_names()) names += (names.empty() ? "" : " ") + n;
  const std::string note = default_note.empty() ? "" : " (" + default_note + ")";
  c->add_option("--metal", f.text["metal"], "Built-in optical constants: " + names + note);
  // Optical constants of real materials lie far inside these bounds (metals: n 0.03-10,
  // k 0-100 over 100 nm - 20 um); beyond them a value is a typo, and the Fresnel terms overflow.
  c->add_option("--n", f.text["n"], "Constant refractive index n (with --k)")
      ->check(positive_number(1e3));
  c->add_option("--k", f.text["k"], "Constant extinction coefficient k (with --n)")
      ->check(number_in(0, 1e3));
  c->add_option("--nk-csv", f.text["nk_csv"], "CSV file 'wavelength_nm,n,k' of optical constants");
  c->add_option("--r0", f.text["r0"],
                "Normal-incidence reflectance in [0, 1) (Sun 2002 5.2: eta = 1, "
                "kappa = 2 sqrt(R0/(1-R0)))")
      ->check(number_in(0, 0.999999));
  c->add_option("--color,--rgb", f.text["color"],
                "sRGB colour 'r,g,b' (0..1 or 0..255) or '#rrggbb': smooth spectrum, eta = 1");
  c->add_option("--fresnel", f.text["fresnel"],
                "exact (complex-index Fresnel equations, default) or schlick");
}

void add_model_flags(CLI::App* c, SpecFlags& f) {
  c->add_option("--model", f.text["model"],
                "Analytic NDF: " + ndf_model_names(", ") + " (default: ggx)");
  // alpha 10 is a slope spread of 84 deg: rougher has no meaning for a microfacet model.
  c->add_option("--alpha", f.text["alpha"], "Roughness alpha (both axes)")
      ->check(positive_number(10));
  c->add_option("--alpha-x", f.text["alpha_x"], "Roughness along the first axis")
      ->check(positive_number(10));
  c->add_option("--alpha-y", f.text["alpha_y"],
                "Roughness along the second axis (default: = alpha-x)")
      ->check(positive_number(10));
  c->add_option("--phi", f.text["phi"],
                "beckmann/ggx: azimuth of the alpha-x axis (angle: 5deg, 0.1rad; bare = deg)")
      ->check(direction());
  c->add_option("--theta-x", f.text["theta_x"],
                "ellipsoid: rotation Rx, tilts the peak towards +y (angle; bare = deg)")
      ->check(direction());
  c->add_option("--theta-y", f.text["theta_y"],
                "ellipsoid: rotation Ry, tilts the peak towards -x (angle; bare = deg)")
      ->check(direction());
  c->add_option("--theta-z", f.text["theta_z"],
                "ellipsoid: rotation Rz, turns the axes by -theta_z (angle; bare = deg)")
      ->check(direction());
  // The other parameters of the registered models (e.g. --gamma), named by the registry.
  for (const auto& p : ndf_model_params()) {
    if (f.text.count(p.name)) continue;
    std::string flag = "--";
    flag += p.name;
    std::replace(flag.begin(), flag.end(), '_', '-');
    std::string models;
    for (const NdfModel* m : ndf_models())
      for (const auto& q : m->params())
        if (q.name == p.name) {
          if (!models.empty()) models += '/';
          models += m->name();
        }
    c->add_option(flag, f.text[p.name], models + ": " + p.help);
  }
}

void add_export_source_flags(CLI::App* c, SpecFlags& f) {
  add_brdf_flags(c, f, (kFlagAllBrdfs & ~kFlagMirror) | kFlagTexture);
  add_material_flags(c, f, "required with a BRDF that has a Fresnel term");
}

void add_brdf_flags(CLI::App* c, SpecFlags& f, unsigned set) {
  if (set & kFlagModel) add_model_flags(c, f);
  if (set & kFlagNdf)
    c->add_option("--ndf", f.text["ndf"],
                  "Tabulated NDF (.npy + .json sidecar, or .exr; from `microbrdf ndf` or "
                  "`tabulate`) instead of --model/--alpha");
  if (set & kFlagKirchhoff)
    c->add_option("--kirchhoff", f.kirchhoff,
                  "Kirchhoff BRDF (Dong eq. 8) from D_K tables of `microbrdf ndf --method "
                  "kirchhoff` (a stack over lambda_q, interpolated per direction; repeat the flag "
                  "to add tables); shadowing from --model/--alpha "
                  "if given");
  if (set & kFlagSun)
    c->add_option("--sun", f.text["sun"], "Sun 2002 analytic BRDF with smoothness s = tau/sigma")
        ->check(positive_number(1e3));
  if (set & kFlagSh) {
    c->add_option("--sh", f.text["sh"],
                  "Spherical-harmonic BRDF file (.shbrdf, Westin 1992; from `simulate` or `brdf "
                  "sh-project`): grey and complete, so no material");
    c->add_option("--l-filter", f.text["l_filter"],
                  "With --sh: Gibbs damping, keep l <= L_FILTER, attenuate above by "
                  "exp(-(l-L_FILTER)^2/(2 WIDTH^2))")
        ->check(count_in(0, 1000));
    c->add_option("--filter-width", f.text["filter_width"],
                  "With --sh: the damping width WIDTH (in l)")
        ->check(positive_number(1000));
    c->add_flag("--isotropic-average", f.isotropic_average,
                "With --sh: average over rotations about n (surfaces known to be isotropic)");
  }
  if (set & kFlagTexture)
    c->add_option("--texture", f.text["texture"],
                  "Ellipsoid parameter texture (.exr) from `microbrdf texture`, with the "
                  "material's Fresnel term");
  if (set & kFlagLambertian)
    c->add_option("--lambertian", f.text["lambertian"],
                  "A Lambertian reflector of this albedo in [0, 1] (no material)")
        ->check(number_in(0, 1));
  if (set & kFlagMirror)
    c->add_flag("--mirror", f.mirror, "Ideal mirror with the material's Fresnel term");
  if (set & (kFlagModel | kFlagNdf))
    c->add_flag("--multiple-scattering", f.multiple_scattering,
                "With --model/--alpha or --ndf: add light that bounces between microfacets more "
                "than once (microfacet random walk, Heitz 2016; docs/multiple_scattering.md)");
  if (set & (kFlagModel | kFlagNdf))
    c->add_option("--ms-walks", f.text["ms_walks"],
                  "With --multiple-scattering: random walks per BRDF value (noise ~ "
                  "1/sqrt(N); default 64, render 4)")
        ->check(count_in(1, 1e6));
  if (set & kFlagSeparable)
    c->add_flag("--separable-g", f.separable_g,
                "Separable Smith G1 G1 (Dong eq. 13) instead of height-correlated");
}

MaterialSpec material_spec(const SpecFlags& f, const std::optional<MaterialSpec>& fallback) {
  return parse_material(f.keys(), fallback, KeyStyle::Cli);
}

BrdfSpec brdf_spec(const SpecFlags& f, const std::optional<BrdfSpec>& fallback) {
  const nlohmann::json keys = f.keys();
  BrdfSpec b = parse_brdf(keys, fallback, KeyStyle::Cli);
  if (!b.uses_material() && has_material(keys))
    throw InputError(std::string(b.kind == BrdfSpec::Kind::Sh ? "--sh: the SH BRDF is grey and "
                                                                "complete"
                                                              : "--lambertian: no Fresnel term") +
                     "; material flags (--metal, --n/--k, --nk-csv, --r0, --color) do not apply");
  return b;
}

void warn_single_dk_table(const SpecFlags& f, const std::string& command) {
  if (f.kirchhoff.empty()) return;
  std::size_t layers = 0;  // from the sidecars alone: the tables are read later, once
  for (const auto& path : f.kirchhoff) layers += ndf_file_layers(path);
  if (layers != 1) return;
  std::fprintf(stderr,
               "microbrdf %s: warning: --kirchhoff: one D_K table stands for every direction, "
               "but each direction's lambda_q = 2 lambda / |wi + wo| differs from its lambda_q "
               "away from backscatter (1/cos(theta_i) times lambda at the mirror direction); "
               "`microbrdf ndf --method kirchhoff` writes a stack over lambda_q by default "
               "(docs/kirchhoff.md)\n",
               command.c_str());
}

std::shared_ptr<const Brdf> brdf_from_flags(const SpecFlags& f, BrdfSpec* spec_out) {
  const BrdfSpec b = brdf_spec(f);
  if (spec_out) *spec_out = b;
  return make_brdf(b, b.uses_material() ? material_spec(f, std::nullopt) : MaterialSpec{});
}

void check_spec_files(Preflight& pre, const SpecFlags& f) {
  if (const auto it = f.text.find("metal"); it != f.text.end() && !it->second.empty())
    pre.metal("--metal", it->second);
  for (const char* key : {"nk_csv", "ndf", "sh", "texture"}) {
    const auto it = f.text.find(key);
    if (it != f.text.end() && !it->second.empty())
      pre.input(key_name(key, KeyStyle::Cli), it->second);
  }
  for (const auto& k : f.kirchhoff) pre.input("--kirchhoff", k);
}

NdfSpec ndf_spec(const SpecFlags& f) {
  BrdfSpec fallback;
  fallback.kind = BrdfSpec::Kind::Analytic;
  return parse_brdf(f.keys(), fallback, KeyStyle::Cli).model;
}

}  // namespace microbrdf::cli
