// What Beckmann and GGX share as registry entries: their parameters and JSON.
#include "models/ndf_builtin.hpp"

namespace microbrdf {

const std::vector<NdfParam>& anisotropic_params() {
  // alpha 10 is a slope spread of 84 deg: rougher has no meaning for a microfacet model.
  static const std::vector<NdfParam> p = {
      {"alpha_x", "1", "Roughness along the first axis", NdfParam::Kind::Alpha, 0, 10, 0.1},
      {"alpha_y", "1", "Roughness along the second axis", NdfParam::Kind::Alpha, 0, 10, 0.1},
      {"phi", "rad", "Azimuth of the alpha_x axis", NdfParam::Kind::Azimuth, -1e300, 1e300, 0}};
  return p;
}

nlohmann::json legacy_anisotropic_json(const std::vector<double>& v) {
  return {{"alpha_x", v[0]}, {"alpha_y", v[1]}, {"phi", v[2]},
          {"theta_x", 0.0},  {"theta_y", 0.0},  {"theta_z", -v[2] + 0.0}};
}

}  // namespace microbrdf
