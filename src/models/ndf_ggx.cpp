// GGX / Trowbridge-Reitz as a registry entry (ndf_model.hpp): D in microfacet_lobes.hpp,
// Lambda and visible-normal sampling in GgxDistribution (microfacet.cpp).
#include "microbrdf/ndf_model_template.hpp"
#include "models/anisotropic_gradient.hpp"
#include "models/microfacet_lobes.hpp"
#include "models/ndf_builtin.hpp"

namespace microbrdf {
namespace {

struct GgxUnit {
  static constexpr int kParams = 3;
  template <typename T>
  using Lobe = lobes::Ggx<T>;
};

class GgxModel final : public AnisotropicModel<GgxUnit, true> {
 public:
  std::string name() const override { return "ggx"; }
  std::string label() const override { return "GGX"; }
  std::vector<std::string> aliases() const override { return {"trowbridge-reitz", "gtr2"}; }
  std::string summary() const override {
    return "GGX / Trowbridge-Reitz (alpha_x, alpha_y, phi); Heitz 2018 visible normals";
  }
  std::shared_ptr<MicrofacetDistribution> make(const std::vector<double>& v) const override {
    return std::make_shared<GgxDistribution>(v[0], v[1], v[2]);
  }
  NdfExportLobe export_lobe(const std::vector<double>& v) const override {
    NdfExportLobe e;
    e.alpha_x = v[0];
    e.alpha_y = v[1];
    e.phi = v[2];
    return e;
  }
};

}  // namespace

std::unique_ptr<NdfModel> make_ggx_model() { return std::make_unique<GgxModel>(); }

}  // namespace microbrdf
