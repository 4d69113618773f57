#pragma once
// The registry of analytic NDF models: each model (ellipsoid, Beckmann, GGX, ...) is one unit
// that says its name and aliases, its parameters (names, units, bounds, defaults), builds its
// MicrofacetDistribution, evaluates D and its derivatives for the fits, maps itself to the
// renderers' materials. Commands, scene JSON, Python, `fit`,
// `tabulate`, export, render and the report look models up here instead of naming them.
// How to add a model: docs/architecture.md ("How to add a reflectance model").
//
// Parameter values are in the model's own units (alphas dimensionless, angles in rad). The fits
// work on a transformed vector ("fit space"): log(v) for alphas, log(v - lo) for positive shape
// exponents (NdfParam::Kind::Exponent), v itself for angles and weights.

#include <cstddef>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "microbrdf/microfacet.hpp"

namespace microbrdf {

/// One parameter of a model.
struct NdfParam {
  /// Alpha: a roughness (fit in log, lower bound from the table's spacing, upper 4, scaled by the
  /// fit's multi-start); Tilt: a rotation bounded to +-1.2 rad in fits; Azimuth: a free in-plane
  /// angle; Exponent: a shape exponent > lo (fit as log(v - lo), bounded by hi); Weight: in
  /// [lo, hi], fitted as is.
  enum class Kind { Alpha, Tilt, Azimuth, Exponent, Weight };
  std::string name;  ///< JSON key and flag stem ("alpha_x" -> --alpha-x)
  std::string unit;  ///< "1" or "rad"
  std::string help;  ///< one line for --help
  Kind kind = Kind::Alpha;
  double lo = 0, hi = 0;  ///< the valid range (open at lo for Alpha and Exponent)
  double def = 0;         ///< default value
};

/// The values of a model's parameters, by name (order of NdfModel::params()).
struct NdfParams {
  std::vector<std::string> names;
  std::vector<double> values;
  bool has(const std::string& name) const;
  /// Throws std::out_of_range naming the parameter when absent.
  double at(const std::string& name) const;
  double& at(const std::string& name);
  /// The value, or `fallback` when the model has no such parameter.
  double get(const std::string& name, double fallback) const;
  std::size_t size() const { return values.size(); }
};

/// D at the nodes of one row of a table and its derivatives with respect to the fit-space
/// parameters; made by NdfModel::evaluator for one parameter vector.
class NdfEvaluator {
 public:
  virtual ~NdfEvaluator() = default;
  /// For i < n, at x = x0 + i h (on this row's y): val[i] = D(x, y, sqrt(1 - x^2 - y^2)) (0 on
  /// and outside the unit disk) and, when grad != nullptr, grad[p stride + i] = dD / d fit_p.
  virtual void row(double x0, double h, std::size_t n, double y, double* val, double* grad,
                   std::size_t stride) const = 0;
};

/// The slope moments of a table, from which every model takes its starting point.
struct NdfMoments {
  double alpha_x = 0.1, alpha_y = 0.1;  ///< sqrt(2 lambda) of the slope covariance's eigenvalues
  double phi = 0;                       ///< azimuth of the alpha_x axis (rad, in (-pi/2, pi/2])
  Vec3 mean_normal = Vec3(0, 0, 1);     ///< integral D m dw
};

/// A renderer's stand-in for a model: GGX alphas (and phi) or nothing.
struct NdfExportLobe {
  bool exact = true;  ///< false: the exporters fit GGX (`note` says what has no equivalent)
  double alpha_x = 0.1, alpha_y = 0.1, phi = 0;
  std::string note;
};

class NdfModel {
 public:
  virtual ~NdfModel() = default;
  /// Canonical name ("ggx"), lower case.
  virtual std::string name() const = 0;
  /// The name in prose ("GGX", "Beckmann"); default name().
  virtual std::string label() const { return name(); }
  /// Other accepted names ("trowbridge-reitz", "gtr2").
  virtual std::vector<std::string> aliases() const { return {}; }
  /// One line for --help and the docs.
  virtual std::string summary() const = 0;
  virtual const std::vector<NdfParam>& params() const = 0;

  /// The distribution with these values (size params().size()); throws InputError for values
  /// outside the model's range.
  virtual std::shared_ptr<MicrofacetDistribution> make(const std::vector<double>& v) const = 0;
  /// The values from the starting moments (defaults for what the moments do not say).
  virtual std::vector<double> initial(const NdfMoments& m) const;
  /// Starting points the fit compares (by cost, each with its alpha scalings) before it starts:
  /// initial() by default; models with shape parameters or several lobes add more.
  virtual std::vector<std::vector<double>> starts(const NdfMoments& m) const {
    return {initial(m)};
  }
  /// Models whose own fits start this one's (a mixture: its two lobes; none by default). The fit
  /// fits them first, to the same table, and also solves from seeded_starts() of their results.
  virtual std::vector<const NdfModel*> seeds() const { return {}; }
  /// Starting points from the fitted values of seeds() (in that order). A mixture's include each
  /// lobe's fit alone (weight 1 or 0), so that its fit never ends above its better lobe's.
  virtual std::vector<std::vector<double>> seeded_starts(
      const std::vector<std::vector<double>>& fitted) const {
    (void)fitted;
    return {};
  }
  /// Brings fitted values to their canonical form (angles folded; equivalent parameter sets
  /// mapped to one), without changing D.
  virtual void canonicalise(std::vector<double>& v) const;
  /// D and its fit-space derivatives for one parameter vector in fit space. `reference`: the
  /// automatic derivatives of the model's one D template even where a faster hand-written
  /// gradient exists (the Ceres path and the tests use it).
  virtual std::unique_ptr<NdfEvaluator> evaluator(const double* fit, bool reference) const = 0;
  /// The material renderers without this NDF get: GGX is what Mitsuba 3, pbrt-v4 and glTF
  /// share. exact = false: the exporters fit GGX to a table of the model and pass `note` on.
  virtual NdfExportLobe export_lobe(const std::vector<double>& v) const;
  /// The fit's JSON "params" (default: the named values; the older models add their legacy
  /// keys so that no key is ever renamed).
  virtual nlohmann::json params_json(const std::vector<double>& v) const;

  // Fit-space transform (per NdfParam::Kind) and its inverse.
  std::vector<double> to_fit(const std::vector<double>& v) const;
  std::vector<double> from_fit(const double* fit) const;
  NdfParams named(const std::vector<double>& v) const;
  /// The values of `p` in this model's order; missing names take their defaults.
  std::vector<double> values(const NdfParams& p) const;
  /// True when the model has a parameter of this kind.
  bool has_kind(NdfParam::Kind k) const;
};

/// The model of that name or alias (case-insensitive); "mixture:A+B" builds the two-lobe model
/// of any two registered models. Throws InputError listing the known names.
const NdfModel& ndf_model(const std::string& name);
/// Every registered model (built-ins first, in registration order; mixtures not included).
std::vector<const NdfModel*> ndf_models();
/// "ellipsoid | beckmann | ggx | ..." for messages and --help.
std::string ndf_model_names(const std::string& separator = " | ");
/// Adds a model (its name and aliases must be new; throws std::logic_error otherwise). The
/// built-ins are registered on first use of the registry; programs and tests may add more.
void register_ndf_model(std::unique_ptr<NdfModel> model);
/// The NdfSpec (the vocabulary of commands and scene files) of a model's named values: the
/// spec's own fields where it has them, the rest in NdfSpec::extra.
NdfSpec ndf_spec(const std::string& model, const NdfParams& p);

/// The ellipsoid's parameters by name and back (its own struct, microfacet.hpp).
NdfParams ndf_params(const EllipsoidParams& p);
EllipsoidParams ellipsoid_params(const NdfParams& p);

/// Every parameter name of every registered model, each once (the BRDF vocabulary's keys).
std::vector<NdfParam> ndf_model_params();

}  // namespace microbrdf
