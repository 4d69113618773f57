// The registry of analytic NDF models (include/microbrdf/ndf_model.hpp) and make_distribution.
#include "microbrdf/ndf_model.hpp"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <stdexcept>

#include "microbrdf/error.hpp"
#include "models/ndf_mixture.hpp"

namespace microbrdf {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

struct Registry {
  std::mutex mutex;
  std::vector<std::unique_ptr<NdfModel>> models;
  std::vector<std::unique_ptr<NdfModel>> mixtures;  // built on demand, kept for the program

  void add(std::unique_ptr<NdfModel> m) {
    std::vector<std::string> names = m->aliases();
    names.push_back(m->name());
    for (const auto& n : names)
      for (const auto& o : models) {
        std::vector<std::string> taken = o->aliases();
        taken.push_back(o->name());
        if (std::find(taken.begin(), taken.end(), lower(n)) != taken.end())
          throw std::logic_error("NDF model name '" + n + "' registered twice");
      }
    models.push_back(std::move(m));
  }
};

}  // namespace

// The built-in models' registry entries (src/models/ndf_<name>.cpp).
std::unique_ptr<NdfModel> make_ellipsoid_model();
std::unique_ptr<NdfModel> make_beckmann_model();
std::unique_ptr<NdfModel> make_ggx_model();
std::unique_ptr<NdfModel> make_student_t_model();

namespace {

Registry& registry() {
  // The built-in models, one line each (a new model: its file, its declaration above and one
  // line here).
  static Registry* r = [] {
    auto* reg = new Registry;
    reg->add(make_ellipsoid_model());
    reg->add(make_beckmann_model());
    reg->add(make_ggx_model());
    reg->add(make_student_t_model());
    return reg;
  }();
  return *r;
}

// The NdfSpec field that holds a parameter of that name, nullptr when it goes to extra.
double* spec_field(NdfSpec& s, const std::string& name) {
  if (name == "alpha_x") return &s.alpha_x;
  if (name == "alpha_y") return &s.alpha_y;
  if (name == "phi") return &s.phi;
  if (name == "theta_x") return &s.theta_x;
  if (name == "theta_y") return &s.theta_y;
  if (name == "theta_z") return &s.theta_z;
  return nullptr;
}

const NdfModel* find_locked(Registry& reg, const std::string& name) {
  for (const auto& m : reg.models) {
    if (m->name() == name) return m.get();
    for (const auto& a : m->aliases())
      if (a == name) return m.get();
  }
  return nullptr;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
bool NdfParams::has(const std::string& name) const {
  return std::find(names.begin(), names.end(), name) != names.end();
}
double NdfParams::at(const std::string& name) const {
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end()) throw std::out_of_range("no NDF parameter '" + name + "'");
  return values[static_cast<std::size_t>(it - names.begin())];
}
double& NdfParams::at(const std::string& name) {
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end()) throw std::out_of_range("no NDF parameter '" + name + "'");
  return values[static_cast<std::size_t>(it - names.begin())];
}
double NdfParams::get(const std::string& name, double fallback) const {
  return has(name) ? at(name) : fallback;
}

// ---------------------------------------------------------------------------------------------
std::vector<double> NdfModel::initial(const NdfMoments& m) const {
  std::vector<double> v;
  for (const auto& p : params()) {
    if (p.name == "alpha_x")
      v.push_back(m.alpha_x);
    else if (p.name == "alpha_y")
      v.push_back(m.alpha_y);
    else if (p.name == "phi")
      v.push_back(m.phi);
    else if (p.name == "theta_z")
      v.push_back(-m.phi);
    else
      v.push_back(p.def);
  }
  return v;
}

void NdfModel::canonicalise(std::vector<double>& v) const {
  // An in-plane azimuth of a mirror-symmetric lobe is defined modulo pi: into [-pi/2, pi/2).
  for (std::size_t i = 0; i < params().size(); ++i)
    if (params()[i].kind == NdfParam::Kind::Azimuth) {
      double t = -v[i];  // folded as theta_z = -phi into (-pi/2, pi/2]
      const double k = std::ceil((t - kPi / 2) / kPi);
      t -= k * kPi;
      if (t <= -kPi / 2) t += kPi;
      v[i] = -t;
    }
}

NdfExportLobe NdfModel::export_lobe(const std::vector<double>&) const {
  NdfExportLobe e;
  e.exact = false;
  return e;
}

nlohmann::json NdfModel::params_json(const std::vector<double>& v) const {
  nlohmann::json j = nlohmann::json::object();
  for (std::size_t i = 0; i < params().size(); ++i) j[params()[i].name] = v[i];
  return j;
}

std::vector<double> NdfModel::to_fit(const std::vector<double>& v) const {
  std::vector<double> f(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    const auto& p = params()[i];
    f[i] = p.kind == NdfParam::Kind::Alpha      ? std::log(v[i])
           : p.kind == NdfParam::Kind::Exponent ? std::log(v[i] - p.lo)
                                                : v[i];
  }
  return f;
}

std::vector<double> NdfModel::from_fit(const double* f) const {
  std::vector<double> v(params().size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    const auto& p = params()[i];
    v[i] = p.kind == NdfParam::Kind::Alpha      ? std::exp(f[i])
           : p.kind == NdfParam::Kind::Exponent ? p.lo + std::exp(f[i])
                                                : f[i];
  }
  return v;
}

NdfParams NdfModel::named(const std::vector<double>& v) const {
  NdfParams n;
  for (const auto& p : params()) n.names.push_back(p.name);
  n.values = v;
  n.values.resize(n.names.size(), 0.0);
  return n;
}

std::vector<double> NdfModel::values(const NdfParams& p) const {
  std::vector<double> v;
  for (const auto& q : params()) v.push_back(p.get(q.name, q.def));
  return v;
}

bool NdfModel::has_kind(NdfParam::Kind k) const {
  for (const auto& p : params())
    if (p.kind == k) return true;
  return false;
}

// ---------------------------------------------------------------------------------------------
const NdfModel& ndf_model(const std::string& name) {
  Registry& reg = registry();
  const std::string n = lower(name);
  std::lock_guard<std::mutex> lock(reg.mutex);
  if (const NdfModel* m = find_locked(reg, n)) return *m;
  if (n.rfind("mixture:", 0) == 0) {
    for (const auto& m : reg.mixtures)
      if (m->name() == n) return *m;
    const std::string lobes = n.substr(8);
    const auto plus = lobes.find('+');
    const NdfModel* a =
        plus == std::string::npos ? nullptr : find_locked(reg, lobes.substr(0, plus));
    const NdfModel* b =
        plus == std::string::npos ? nullptr : find_locked(reg, lobes.substr(plus + 1));
    if (!a || !b)
      throw InputError("unknown model '" + name + "': a mixture is mixture:A+B with A, B among " +
                       [&] {
                         std::string s;
                         for (const auto& m : reg.models) s += (s.empty() ? "" : ", ") + m->name();
                         return s;
                       }());
    reg.mixtures.push_back(make_mixture_model(*a, *b));
    return *reg.mixtures.back();
  }
  std::string list;
  for (const auto& m : reg.models) list += (list.empty() ? "" : " | ") + m->name();
  throw InputError("unknown model '" + name + "' (" + list + " | mixture:A+B)");
}

std::vector<const NdfModel*> ndf_models() {
  Registry& reg = registry();
  std::lock_guard<std::mutex> lock(reg.mutex);
  std::vector<const NdfModel*> out;
  for (const auto& m : reg.models) out.push_back(m.get());
  return out;
}

std::string ndf_model_names(const std::string& separator) {
  std::string s;
  for (const NdfModel* m : ndf_models()) s += (s.empty() ? "" : separator) + m->name();
  return s;
}

void register_ndf_model(std::unique_ptr<NdfModel> model) {
  Registry& reg = registry();
  std::lock_guard<std::mutex> lock(reg.mutex);
  reg.add(std::move(model));
}

std::vector<NdfParam> ndf_model_params() {
  std::vector<NdfParam> out;
  for (const NdfModel* m : ndf_models())
    for (const auto& p : m->params())
      if (std::none_of(out.begin(), out.end(), [&](const NdfParam& q) { return q.name == p.name; }))
        out.push_back(p);
  return out;
}

NdfSpec ndf_spec(const std::string& model, const NdfParams& p) {
  NdfSpec s;
  s.model = model;
  for (std::size_t i = 0; i < p.names.size(); ++i) {
    if (double* field = spec_field(s, p.names[i]))
      *field = p.values[i];
    else
      s.extra[p.names[i]] = p.values[i];
  }
  return s;
}

NdfParams ndf_params(const EllipsoidParams& p) {
  return ndf_model("ellipsoid").named({p.alpha_x, p.alpha_y, p.theta_x, p.theta_y, p.theta_z});
}

EllipsoidParams ellipsoid_params(const NdfParams& p) {
  return {p.at("alpha_x"), p.at("alpha_y"), p.at("theta_x"), p.at("theta_y"), p.at("theta_z")};
}

// ---------------------------------------------------------------------------------------------
std::shared_ptr<MicrofacetDistribution> make_distribution(const NdfSpec& s) {
  const NdfModel& model = ndf_model(s.model);
  if (model.name().rfind("mixture:", 0) == 0)
    throw InputError("a mixture is a fit result; give one model (" + ndf_model_names(", ") + ")");
  auto has = [&](const char* n) {
    for (const auto& p : model.params())
      if (p.name == n) return true;
    return false;
  };
  // The angles of the vocabulary belong to some models only: say which flag the model takes.
  const bool tilt = s.theta_x != 0 || s.theta_y != 0 || s.theta_z != 0;
  if (tilt && !has("theta_x"))
    throw InputError("--theta-x/--theta-y/--theta-z belong to the ellipsoid model; " +
                     lower(s.model) + " takes an in-plane rotation --phi");
  if (s.phi != 0 && !has("phi"))
    throw InputError("the " + model.name() + " model " +
                     (has("theta_z") ? "turns its axes with --theta-z, not --phi"
                                     : "has no in-plane rotation --phi"));
  std::vector<double> v;
  NdfSpec spec = s;
  for (const auto& p : model.params()) {
    if (const double* field = spec_field(spec, p.name)) {
      v.push_back(*field);
    } else {
      const auto it = s.extra.find(p.name);
      v.push_back(it != s.extra.end() ? it->second : p.def);
    }
  }
  auto flag = [](std::string k) {
    std::replace(k.begin(), k.end(), '_', '-');
    k.insert(0, "--");
    return k;
  };
  for (const auto& [key, value] : s.extra)
    if (!has(key.c_str()))
      throw InputError(flag(key) + " does not belong to the " + model.name() + " model");
  // Shape exponents and weights: their range here (the distributions check alphas and angles).
  for (std::size_t i = 0; i < v.size(); ++i) {
    const NdfParam& p = model.params()[i];
    const bool open_lo = p.kind == NdfParam::Kind::Exponent;
    if ((open_lo || p.kind == NdfParam::Kind::Weight) &&
        !((open_lo ? v[i] > p.lo : v[i] >= p.lo) && v[i] <= p.hi))
      throw InputError(flag(p.name) + " must lie in " + (open_lo ? "(" : "[") +
                       std::to_string(p.lo) + ", " + std::to_string(p.hi) + "] (got " +
                       std::to_string(v[i]) + ")");
  }
  return model.make(v);
}

}  // namespace microbrdf
