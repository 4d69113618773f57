// The one BRDF vocabulary and its factory (include/microbrdf/brdf_spec.hpp).
#include "microbrdf/brdf_spec.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "microbrdf/brdf.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/kirchhoff_brdf.hpp"
#include "microbrdf/lambertian_brdf.hpp"
#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/mirror_brdf.hpp"
#include "microbrdf/multiple_scattering.hpp"
#include "microbrdf/ndf_io.hpp"
#include "microbrdf/ndf_model.hpp"
#include "microbrdf/sh_brdf.hpp"
#include "microbrdf/sun2002.hpp"
#include "microbrdf/sun_brdf.hpp"
#include "microbrdf/tabulated_distribution.hpp"
#include "microbrdf/units.hpp"

namespace microbrdf {
namespace {

using nlohmann::json;

struct Reader {
  const json& keys;
  KeyStyle style;
  bool given(const char* k) const {
    return keys.is_object() && keys.contains(k) && !keys.at(k).is_null();
  }
  std::string name(const char* k) const { return key_name(k, style); }
  std::string text(const char* k) const { return spec_text(keys.at(k), k, style); }
  double number(const char* k) const { return spec_number(keys.at(k), k, style); }
  // An angle: a string with a unit (a bare number in a string is degrees, as on the command
  // line) or a JSON number (degrees). Radians.
  double angle(const char* k) const {
    const json& v = keys.at(k);
    if (v.is_number()) return v.get<double>() * M_PI / 180;
    if (!v.is_string()) throw InputError(name(k) + " must be an angle such as \"5deg\"");
    try {
      return parse_angle(v.get<std::string>());
    } catch (const InputError& e) {
      throw InputError(name(k) + ": " + e.what());
    }
  }
  bool flag(const char* k) const {
    if (!given(k)) return false;
    const json& v = keys.at(k);
    if (v.is_boolean()) return v.get<bool>();
    if (v.is_string() && (v == "true" || v == "1")) return true;
    if (v.is_string() && (v == "false" || v == "0")) return false;
    throw InputError(name(k) + " must be true or false (got " + v.dump() + ")");
  }
};

}  // namespace

// The registered models' parameters beyond the vocabulary's own (e.g. "gamma"): numbers.
std::vector<std::string> model_extra_keys() {
  std::vector<std::string> out;
  for (const auto& p : ndf_model_params())
    if (p.name != "alpha_x" && p.name != "alpha_y" && p.name != "phi" && p.name != "theta_x" &&
        p.name != "theta_y" && p.name != "theta_z")
      out.push_back(p.name);
  return out;
}

const std::vector<std::string>& brdf_keys() {
  static const std::vector<std::string> keys = [] {
    std::vector<std::string> k = {
        "model",   "alpha",      "alpha_x",  "alpha_y",      "phi",
        "theta_x", "theta_y",    "theta_z",  "ndf",          "kirchhoff",
        "sun",     "sh",         "l_filter", "filter_width", "isotropic_average",
        "texture", "lambertian", "mirror",   "separable_g",  "multiple_scattering",
        "ms_walks"};
    for (const auto& e : model_extra_keys()) k.push_back(e);
    return k;
  }();
  return keys;
}

bool BrdfSpec::uses_material() const { return kind != Kind::Sh && kind != Kind::Lambertian; }

BrdfSpec parse_brdf(const json& keys, const std::optional<BrdfSpec>& fallback, KeyStyle style) {
  const Reader r{keys, style};
  bool model_keys = r.given("model") || r.given("alpha") || r.given("alpha_x") ||
                    r.given("alpha_y") || r.given("phi") || r.given("theta_x") ||
                    r.given("theta_y") || r.given("theta_z");
  for (const auto& e : model_extra_keys()) model_keys = model_keys || r.given(e.c_str());
  const bool kirchhoff = r.given("kirchhoff");
  std::vector<std::string> kinds;
  if (model_keys && !kirchhoff) kinds.push_back(r.name("model") + "/" + r.name("alpha"));
  if (r.given("ndf")) kinds.push_back(r.name("ndf"));
  if (kirchhoff) kinds.push_back(r.name("kirchhoff"));
  if (r.given("sun")) kinds.push_back(r.name("sun"));
  if (r.given("sh")) kinds.push_back(r.name("sh"));
  if (r.given("texture")) kinds.push_back(r.name("texture"));
  if (r.given("lambertian")) kinds.push_back(r.name("lambertian"));
  if (r.flag("mirror")) kinds.push_back(r.name("mirror"));
  if (r.given("ndf") && model_keys)
    throw InputError(r.name("ndf") + " replaces the analytic model: do not combine it with " +
                     r.name("model") + ", " + r.name("alpha") + "*, " + r.name("phi") + " or " +
                     r.name("theta_x") + "/y/z");
  if (kinds.size() > 1) {
    std::string list;
    for (const auto& k : kinds) list += (list.empty() ? "" : ", ") + k;
    throw InputError("give one BRDF, not " + list);
  }
  BrdfSpec s;
  if (kinds.empty()) {
    if (!fallback)
      throw InputError("give a BRDF: " + r.name("model") + "/" + r.name("alpha") + " (analytic), " +
                       r.name("ndf") + " FILE, " + r.name("kirchhoff") + " FILE, " + r.name("sun") +
                       " S, " + r.name("sh") + " FILE, " + r.name("texture") + " FILE, " +
                       r.name("lambertian") + " ALBEDO or " + r.name("mirror"));
    s = *fallback;
  } else if (r.given("ndf")) {
    s.kind = BrdfSpec::Kind::Tabulated;
    s.ndf = r.text("ndf");
  } else if (kirchhoff) {
    s.kind = BrdfSpec::Kind::Kirchhoff;
    const json& v = keys.at("kirchhoff");
    if (v.is_array()) {
      for (const auto& f : v) {
        if (!f.is_string()) throw InputError(r.name("kirchhoff") + " must name files");
        s.kirchhoff.push_back(f.get<std::string>());
      }
    } else {
      s.kirchhoff.push_back(r.text("kirchhoff"));
    }
    if (s.kirchhoff.empty()) throw InputError(r.name("kirchhoff") + ": give a D_K table");
  } else if (r.given("sun")) {
    s.kind = BrdfSpec::Kind::Sun;
    s.sun_s = r.number("sun");
    if (!(s.sun_s > 0)) throw InputError(r.name("sun") + ": the smoothness s must be > 0");
  } else if (r.given("sh")) {
    s.kind = BrdfSpec::Kind::Sh;
    s.sh = r.text("sh");
  } else if (r.given("texture")) {
    s.kind = BrdfSpec::Kind::Texture;
    s.texture = r.text("texture");
  } else if (r.given("lambertian")) {
    s.kind = BrdfSpec::Kind::Lambertian;
    s.lambertian_albedo = r.number("lambertian");
    if (!(s.lambertian_albedo >= 0 && s.lambertian_albedo <= 1))
      throw InputError(r.name("lambertian") + ": the albedo must lie in [0, 1]");
  } else if (r.flag("mirror")) {
    s.kind = BrdfSpec::Kind::Mirror;
  } else {
    s.kind = BrdfSpec::Kind::Analytic;
  }
  if (model_keys) {
    s.model_given = true;
    if (r.given("model")) s.model.model = r.text("model");
    const double alpha = r.given("alpha") ? r.number("alpha") : 0;
    const double ax = r.given("alpha_x") ? r.number("alpha_x") : 0;
    const double ay = r.given("alpha_y") ? r.number("alpha_y") : 0;
    s.model.alpha_x = ax > 0 ? ax : alpha;
    s.model.alpha_y = ay > 0 ? ay : (alpha > 0 ? alpha : s.model.alpha_x);
    // (Models without alpha_x, e.g. one with a single roughness parameter of its own, do not
    // need it; an unknown model is reported when the distribution is made.)
    bool needs_alpha = true;
    try {
      const auto& ps = ndf_model(s.model.model).params();
      needs_alpha =
          std::any_of(ps.begin(), ps.end(), [](const NdfParam& p) { return p.name == "alpha_x"; });
    } catch (const InputError&) {
    }
    if (needs_alpha && !(s.model.alpha_x > 0))
      throw InputError("give the roughness: " + r.name("alpha") + ", or " + r.name("alpha_x") +
                       " (and " + r.name("alpha_y") + ")");
    if (r.given("phi")) s.model.phi = r.angle("phi");
    if (r.given("theta_x")) s.model.theta_x = r.angle("theta_x");
    if (r.given("theta_y")) s.model.theta_y = r.angle("theta_y");
    if (r.given("theta_z")) s.model.theta_z = r.angle("theta_z");
    for (const auto& e : model_extra_keys())
      if (r.given(e.c_str())) s.model.extra[e] = r.number(e.c_str());
  } else if (s.kind == BrdfSpec::Kind::Analytic && !s.model_given) {
    throw InputError("give the roughness: " + r.name("alpha") + ", or " + r.name("alpha_x") +
                     " (and " + r.name("alpha_y") + ")");
  }
  const bool damping = r.given("l_filter") || r.given("filter_width");
  if ((damping || r.given("isotropic_average")) && s.kind != BrdfSpec::Kind::Sh)
    throw InputError(r.name("l_filter") + ", " + r.name("filter_width") + " and " +
                     r.name("isotropic_average") + " apply to " + r.name("sh") + " only");
  if (damping) {
    const double lf = r.given("l_filter") ? r.number("l_filter") : -1;
    s.sh_filter_width = r.given("filter_width") ? r.number("filter_width") : 0;
    if (!(lf >= 0) || lf != std::floor(lf) || !(s.sh_filter_width > 0))
      throw InputError(r.name("l_filter") + " and " + r.name("filter_width") +
                       " go together (l_filter >= 0, width > 0)");
    s.sh_l_filter = static_cast<int>(lf);
  }
  s.sh_isotropic_average = r.flag("isotropic_average");
  s.separable_g = r.flag("separable_g");
  if (s.separable_g && s.kind != BrdfSpec::Kind::Analytic && s.kind != BrdfSpec::Kind::Tabulated)
    throw InputError(r.name("separable_g") + " applies to microfacet BRDFs (" + r.name("model") +
                     " or " + r.name("ndf") + ") only");
  s.multiple_scattering = r.flag("multiple_scattering");
  if (s.multiple_scattering && s.kind != BrdfSpec::Kind::Analytic &&
      s.kind != BrdfSpec::Kind::Tabulated)
    throw InputError(r.name("multiple_scattering") + " applies to microfacet BRDFs (" +
                     r.name("model") + " or " + r.name("ndf") + ") only");
  if (r.given("ms_walks")) {
    const double w = r.number("ms_walks");
    if (!s.multiple_scattering)
      throw InputError(r.name("ms_walks") + " goes with " + r.name("multiple_scattering"));
    if (!(w >= 1 && w <= 1e6) || w != std::floor(w))
      throw InputError(r.name("ms_walks") + " must be a whole number in [1, 1000000]");
    s.ms_walks = static_cast<int>(w);
  }
  if (s.multiple_scattering && s.separable_g)
    throw InputError(r.name("multiple_scattering") + " and " + r.name("separable_g") +
                     " exclude each other: the random walk's first order is the "
                     "height-correlated G2");
  return s;
}

std::shared_ptr<const Brdf> make_microfacet_brdf(std::shared_ptr<const MicrofacetDistribution> d,
                                                 std::shared_ptr<const Fresnel> f,
                                                 const BrdfSpec& spec) {
  if (spec.multiple_scattering) {
    MultipleScatteringOptions o;
    o.eval_walks = spec.ms_walks > 0 ? spec.ms_walks : kDefaultMsWalks;
    return std::make_shared<MultipleScatteringBrdf>(std::move(d), std::move(f), o);
  }
  return std::make_shared<MicrofacetBrdf>(std::move(d), std::move(f), spec.separable_g);
}

std::string BrdfSpec::describe() const {
  std::ostringstream os;
  switch (kind) {
    case Kind::Analytic:
      os << model.model << " alpha " << model.alpha_x;
      if (model.alpha_y != model.alpha_x) os << " x " << model.alpha_y;
      if (multiple_scattering) os << " + multiple scattering";
      return os.str();
    case Kind::Tabulated:
      return "tabulated NDF " + ndf + (multiple_scattering ? " + multiple scattering" : "");
    case Kind::Kirchhoff:
      return "Kirchhoff D_K " + kirchhoff.front() +
             (kirchhoff.size() > 1 ? " (+" + std::to_string(kirchhoff.size() - 1) + ")" : "");
    case Kind::Sun:
      os << "Sun 2002, s = " << sun_s;
      return os.str();
    case Kind::Sh:
      return "SH BRDF " + sh;
    case Kind::Texture:
      return "parameter texture " + texture;
    case Kind::Lambertian:
      os << "Lambertian, albedo " << lambertian_albedo;
      return os.str();
    case Kind::Mirror:
      return "ideal mirror";
  }
  return "?";
}

std::shared_ptr<const Brdf> make_brdf(const BrdfSpec& s, const MaterialSpec& material) {
  switch (s.kind) {
    case BrdfSpec::Kind::Analytic:
      return make_microfacet_brdf(make_distribution(s.model), make_fresnel(material), s);
    case BrdfSpec::Kind::Tabulated:
      return make_microfacet_brdf(std::make_shared<TabulatedDistribution>(read_ndf(s.ndf)),
                                  make_fresnel(material), s);
    case BrdfSpec::Kind::Kirchhoff: {
      std::vector<TabulatedNdf> tables;
      for (const auto& f : s.kirchhoff)
        for (auto& t : read_ndf_stack(f)) tables.push_back(std::move(t));
      std::shared_ptr<const MicrofacetDistribution> g;
      if (s.model_given) g = make_distribution(s.model);
      return std::make_shared<KirchhoffBrdf>(std::move(tables), make_fresnel(material), g);
    }
    case BrdfSpec::Kind::Sun:
      return std::make_shared<sun2002::SunBrdf>(s.sun_s, sun2002::BrdfForm::Standard,
                                                make_fresnel(material));
    case BrdfSpec::Kind::Sh: {
      auto b = std::make_shared<ShBrdf>(ShBrdf::load(s.sh));
      if (s.sh_l_filter >= 0)
        b = std::make_shared<ShBrdf>(b->damped(s.sh_l_filter, s.sh_filter_width));
      if (s.sh_isotropic_average) b = std::make_shared<ShBrdf>(b->isotropic_average());
      return b;
    }
    case BrdfSpec::Kind::Lambertian:
      return std::make_shared<LambertianBrdf>(s.lambertian_albedo);
    case BrdfSpec::Kind::Mirror:
      return std::make_shared<SpecularMirrorBrdf>(make_fresnel(material));
    case BrdfSpec::Kind::Texture:
      break;
  }
  throw InputError(
      "a parameter texture is spatially varying: it is drawn as an Svbrdf "
      "(make_svbrdf), not a Brdf");
}

}  // namespace microbrdf
