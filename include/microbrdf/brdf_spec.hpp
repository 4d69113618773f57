#pragma once
// The one BRDF vocabulary: which reflectance model, with which parameters, as the command line,
// the scene JSON and the Python module name it, and the one factory that builds it. The
// material (Fresnel term) is a separate MaterialSpec (material_spec.hpp).
//
// Keys (CLI flag = "--" + key with '_' -> '-'; JSON key and Python keyword = key):
//   model        analytic NDF: beckmann, ggx (default) or ellipsoid (Dong 2015 eqs. 10-14)
//   alpha        roughness of both axes (dimensionless, > 0)
//   alpha_x      roughness along the first axis; alpha_y along the second (default alpha_x)
//   phi          beckmann/ggx: azimuth of the alpha_x axis
//   theta_x, theta_y, theta_z   ellipsoid rotations (Dong eqs. 10-14)
//                angles: a number with a unit ("5deg", "0.05rad"); a bare number is degrees
//   ndf          a tabulated NDF file (.npy + sidecar or .exr) instead of an analytic model
//   kirchhoff    D_K table file(s) (Dong eq. 8); an analytic model given with it supplies the
//                shadowing G (several files: one per wavelength lambda_q)
//   sun          Sun 2002's analytic BRDF with smoothness s = tau / sigma (> 0)
//   sh           a spherical-harmonic BRDF file (.shbrdf, Westin 1992): grey and complete, so
//                no material; optional l_filter + filter_width (Gibbs damping, in l) and
//                isotropic_average (true/false)
//   texture      an ellipsoid parameter texture (.exr from `microbrdf texture`): spatially
//                varying, so only make_svbrdf() builds it (texture layer)
//   lambertian   a Lambertian reflector of this albedo in [0, 1] (no material)
//   mirror       an ideal mirror (true/false) with the material's Fresnel term
//   separable_g  microfacet BRDFs: separable Smith G1 G1 (Dong eq. 13) instead of the
//                height-correlated G2
//   multiple_scattering  microfacet BRDFs (model or ndf): add the light that bounces between
//                microfacets more than once (the microfacet random walk of Heitz 2016,
//                multiple_scattering.hpp; true/false, default false)
//   ms_walks     with multiple_scattering: random walks per eval() (its relative noise falls as
//                1/sqrt(ms_walks); cost about 0.5 us per walk); default 64, the preview
//                renderer 4 (its pixels average the noise)
// At most one of: an analytic model (model / alpha*), ndf, kirchhoff, sun, sh, texture,
// lambertian, mirror.

#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "microbrdf/brdf.hpp"
#include "microbrdf/material_spec.hpp"
#include "microbrdf/microfacet.hpp"

namespace microbrdf {

struct BrdfSpec {
  enum class Kind { Analytic, Tabulated, Kirchhoff, Sun, Sh, Texture, Lambertian, Mirror };
  Kind kind = Kind::Analytic;
  bool model_given = false;            ///< model or alpha* keys were given (kirchhoff: shadowing)
  NdfSpec model;                       ///< analytic: model name, alphas, angles in radians
  std::string ndf;                     ///< tabulated: NDF file
  std::vector<std::string> kirchhoff;  ///< kirchhoff: D_K tables
  double sun_s = 0;                    ///< sun: smoothness tau / sigma
  std::string sh;                      ///< sh: .shbrdf file
  int sh_l_filter = -1;                ///< sh: Gibbs damping above this l (-1: none)
  double sh_filter_width = 0;          ///< sh: damping width, in l
  bool sh_isotropic_average = false;   ///< sh: average over rotations about n
  std::string texture;                 ///< texture: parameter texture file
  double lambertian_albedo = 1;        ///< lambertian: albedo in [0, 1]
  bool separable_g = false;            ///< analytic / tabulated: Smith G1 G1 (Dong eq. 13)
  bool multiple_scattering = false;    ///< analytic / tabulated: + orders >= 2 (random walk)
  int ms_walks = 0;                    ///< walks per eval (0: the default, kDefaultMsWalks)

  /// True for the kinds that take a material's Fresnel term (all but sh and lambertian).
  bool uses_material() const;
  /// One line for reports, e.g. "ggx alpha 0.1 x 0.3" or "tabulated NDF ndf.npy".
  std::string describe() const;
};

/// Walks per eval() of a multiple-scattering BRDF when ms_walks is not given.
inline constexpr int kDefaultMsWalks = 64;

/// The BRDF keys, in the order --help lists them.
const std::vector<std::string>& brdf_keys();

/// Reads the BRDF keys of a JSON object (other keys are ignored; values are strings as typed on
/// a command line, numbers or booleans; kirchhoff may be a string or an array of strings).
/// With no kind key the result is `fallback`, or InputError when there is none. Throws
/// InputError naming the key (in `style`) for two kinds at once, keys that do not go with the
/// kind (e.g. l_filter without sh), bad numbers or angles.
BrdfSpec parse_brdf(const nlohmann::json& keys,
                    const std::optional<BrdfSpec>& fallback = std::nullopt,
                    KeyStyle style = KeyStyle::Json);

/// Builds the BRDF (files are read here: FileError names the file). The material is used by
/// every kind but sh and lambertian; for those, a material given explicitly is an error the
/// caller reports (BrdfSpec::uses_material). Throws InputError for the texture kind (spatially
/// varying: make_svbrdf, texture.hpp).
std::shared_ptr<const Brdf> make_brdf(const BrdfSpec& spec, const MaterialSpec& material);

/// The microfacet BRDF of a spec's distribution: MicrofacetBrdf, or MultipleScatteringBrdf
/// (multiple_scattering.hpp) when spec.multiple_scattering is set.
std::shared_ptr<const Brdf> make_microfacet_brdf(std::shared_ptr<const MicrofacetDistribution> d,
                                                 std::shared_ptr<const Fresnel> f,
                                                 const BrdfSpec& spec);

}  // namespace microbrdf
