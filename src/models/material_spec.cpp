// The one material vocabulary and its factory (include/microbrdf/material_spec.hpp).
#include "microbrdf/material_spec.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <sstream>

#include "microbrdf/error.hpp"

namespace microbrdf {
namespace {

using nlohmann::json;

// "r,g,b" in [0, 1] (or 0..255 when a value exceeds 1) or "#rrggbb" -> three values in [0, 1].
std::array<double, 3> parse_color(const std::string& text, KeyStyle style) {
  std::array<double, 3> c{};
  const auto bad = [&] {
    return InputError(key_name("color", style) + ": expected 'r,g,b' or '#rrggbb', got '" + text +
                      "'");
  };
  if (text.size() == 7 && text[0] == '#') {
    for (int i = 0; i < 3; ++i) {
      const std::string h = text.substr(1 + 2 * i, 2);
      if (!std::all_of(h.begin(), h.end(), [](unsigned char ch) { return std::isxdigit(ch); }))
        throw bad();
      c[i] = std::stoi(h, nullptr, 16) / 255.0;
    }
    return c;
  }
  std::string s = text;
  std::replace(s.begin(), s.end(), ',', ' ');
  std::istringstream is(s);
  if (!(is >> c[0] >> c[1] >> c[2])) throw bad();
  std::string rest;
  if (is >> rest) throw bad();
  for (double v : c)
    if (!(v >= 0) || !std::isfinite(v)) throw bad();
  if (c[0] > 1 || c[1] > 1 || c[2] > 1)
    for (double& v : c) v /= 255.0;
  for (double v : c)
    if (v > 1) throw bad();
  return c;
}

}  // namespace

std::string spec_text(const json& v, const std::string& key, KeyStyle style) {
  if (v.is_string()) return v.get<std::string>();
  throw InputError(key_name(key, style) + " must be a string (got " + v.dump() + ")");
}

double spec_number(const json& v, const std::string& key, KeyStyle style) {
  if (v.is_number()) return v.get<double>();
  if (v.is_string()) {
    const std::string s = v.get<std::string>();
    std::size_t used = 0;
    double x = 0;
    try {
      x = std::stod(s, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    while (used < s.size() && std::isspace(static_cast<unsigned char>(s[used]))) ++used;
    if (used == s.size() && !s.empty() && std::isfinite(x)) return x;
  }
  throw InputError(key_name(key, style) + " must be a number (got " + v.dump() + ")");
}

std::string key_name(const std::string& key, KeyStyle style) {
  switch (style) {
    case KeyStyle::Cli: {
      std::string f = "--" + key;
      std::replace(f.begin(), f.end(), '_', '-');
      return f;
    }
    case KeyStyle::Python:
      return key + "=";
    case KeyStyle::Json:
      break;
  }
  return "\"" + key + "\"";
}

const std::vector<std::string>& material_keys() {
  static const std::vector<std::string> keys = {"metal", "n",     "k",      "nk_csv",
                                                "r0",    "color", "fresnel"};
  return keys;
}

bool has_material(const json& keys) {
  if (!keys.is_object()) return false;
  for (const auto& k : material_keys())
    if (k != "fresnel" && keys.contains(k) && !keys.at(k).is_null()) return true;
  return false;
}

MaterialSpec MaterialSpec::named_metal(const std::string& name) {
  MaterialSpec m;
  m.form = Form::Metal;
  m.metal = name;
  return m;
}

MaterialSpec parse_material(const json& keys, const std::optional<MaterialSpec>& fallback,
                            KeyStyle style) {
  const auto given = [&](const char* k) {
    return keys.is_object() && keys.contains(k) && !keys.at(k).is_null();
  };
  const auto name = [&](const char* k) { return key_name(k, style); };
  std::vector<std::string> forms;
  if (given("metal")) forms.push_back(name("metal"));
  if (given("n") || given("k")) forms.push_back(name("n") + "/" + name("k"));
  if (given("nk_csv")) forms.push_back(name("nk_csv"));
  if (given("r0")) forms.push_back(name("r0"));
  if (given("color")) forms.push_back(name("color"));
  if (forms.size() > 1) {
    std::string list;
    for (const auto& f : forms) list += (list.empty() ? "" : ", ") + f;
    throw InputError("give one material, not " + list);
  }
  MaterialSpec m;
  if (forms.empty()) {
    if (!fallback)
      throw InputError("give a material: " + name("metal") + " NAME, " + name("n") + "/" +
                       name("k") + ", " + name("nk_csv") + " FILE, " + name("r0") + " R or " +
                       name("color") + " COLOUR");
    m = *fallback;
  } else if (given("metal")) {
    m.form = MaterialSpec::Form::Metal;
    m.metal = spec_text(keys.at("metal"), "metal", style);
    try {
      (void)metal(m.metal);  // unknown names fail here, before any work
    } catch (const InputError& e) {
      throw InputError(name("metal") + ": " + e.what());
    }
  } else if (given("n") || given("k")) {
    if (!given("n") || !given("k"))
      throw InputError(name("n") + " and " + name("k") + " go together (n > 0, k >= 0)");
    m.form = MaterialSpec::Form::Nk;
    m.n = spec_number(keys.at("n"), "n", style);
    m.k = spec_number(keys.at("k"), "k", style);
    if (!(m.n > 0) || !(m.k >= 0))
      throw InputError(name("n") + " and " + name("k") + " go together (n > 0, k >= 0)");
  } else if (given("nk_csv")) {
    m.form = MaterialSpec::Form::NkCsv;
    m.nk_csv = spec_text(keys.at("nk_csv"), "nk_csv", style);
    if (m.nk_csv.empty()) throw InputError(name("nk_csv") + ": give the CSV file");
  } else if (given("r0")) {
    m.form = MaterialSpec::Form::R0;
    m.r0 = spec_number(keys.at("r0"), "r0", style);
    if (!(m.r0 >= 0 && m.r0 < 1)) throw InputError(name("r0") + " must lie in [0, 1)");
  } else {
    m.form = MaterialSpec::Form::Color;
    m.color = spec_text(keys.at("color"), "color", style);
    (void)parse_color(m.color, style);
  }
  if (given("fresnel")) {
    const std::string f = spec_text(keys.at("fresnel"), "fresnel", style);
    if (f == "exact")
      m.fresnel = FresnelMode::Exact;
    else if (f == "schlick")
      m.fresnel = FresnelMode::Schlick;
    else
      throw InputError(name("fresnel") + " must be exact or schlick (got '" + f + "')");
  }
  return m;
}

OpticalConstants optical_constants(const MaterialSpec& m) {
  switch (m.form) {
    case MaterialSpec::Form::Metal:
      return metal(m.metal);
    case MaterialSpec::Form::Nk:
      return constant_index(m.n, m.k);
    case MaterialSpec::Form::NkCsv:
      return read_optical_constants_csv(m.nk_csv);
    case MaterialSpec::Form::R0:
      return from_normal_reflectance(Spectrum::constant(m.r0), 1.0);
    case MaterialSpec::Form::Color: {
      const auto c = parse_color(m.color, KeyStyle::Json);
      return from_srgb(c[0], c[1], c[2]);
    }
    case MaterialSpec::Form::Perfect:
    case MaterialSpec::Form::Dielectric:
      break;
  }
  throw InputError("this material (" + m.describe() + ") has no optical constants of a metal");
}

std::shared_ptr<const Fresnel> make_fresnel(const MaterialSpec& m) {
  if (m.form == MaterialSpec::Form::Perfect) return std::make_shared<PerfectMirrorFresnel>();
  if (m.form == MaterialSpec::Form::Dielectric) {
    if (!(m.eta > 0)) throw InputError("a dielectric needs eta > 0");
    return std::make_shared<DielectricFresnel>(Spectrum::constant(m.eta));
  }
  const OpticalConstants oc = optical_constants(m);
  if (m.fresnel == FresnelMode::Schlick)
    return std::make_shared<SchlickFresnel>(oc.normal_reflectance_spectrum());
  return std::make_shared<ConductorFresnel>(oc);
}

std::string MaterialSpec::describe() const {
  std::ostringstream os;
  switch (form) {
    case Form::Metal:
      os << "metal " << metal;
      break;
    case Form::Nk:
      os << "n = " << n << ", k = " << k;
      break;
    case Form::NkCsv:
      os << "optical constants " << nk_csv;
      break;
    case Form::R0:
      os << "R0 = " << r0;
      break;
    case Form::Color:
      os << "sRGB colour " << color;
      break;
    case Form::Perfect:
      return "R = 1";
    case Form::Dielectric:
      os << "dielectric eta = " << eta;
      return os.str();
  }
  os << (fresnel == FresnelMode::Schlick ? ", Schlick Fresnel" : ", exact Fresnel");
  return os.str();
}

json MaterialSpec::to_json() const {
  json j;
  switch (form) {
    case Form::Metal:
      j["metal"] = metal;
      break;
    case Form::Nk:
      j["n"] = n;
      j["k"] = k;
      break;
    case Form::NkCsv:
      j["nk_csv"] = nk_csv;
      break;
    case Form::R0:
      j["r0"] = r0;
      break;
    case Form::Color:
      j["color"] = color;
      break;
    case Form::Perfect:
      j["perfect"] = true;
      return j;
    case Form::Dielectric:
      j["eta"] = eta;
      return j;
  }
  j["fresnel"] = fresnel == FresnelMode::Schlick ? "schlick" : "exact";
  return j;
}

}  // namespace microbrdf
