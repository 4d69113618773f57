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

class GgxModel final : public TemplateNdfModel<GgxUnit> {
 public:
  std::string name() const override { return "ggx"; }
  std::string label() const override { return "GGX"; }
  std::vector<std::string> aliases() const override { return {"trowbridge-reitz", "gtr2"}; }
  std::string summary() const override {
    return "GGX / Trowbridge-Reitz (alpha_x, alpha_y, phi); Heitz 2018 visible normals";
  }
  const std::vector<NdfParam>& params() const override { return anisotropic_params(); }
  std::shared_ptr<MicrofacetDistribution> make(const std::vector<double>& v) const override {
    return std::make_shared<GgxDistribution>(v[0], v[1], v[2]);
  }
  std::unique_ptr<NdfEvaluator> evaluator(const double* fit, bool reference) const override {
    auto plain = TemplateNdfModel<GgxUnit>::evaluator(fit, true);
    if (reference) return plain;
    return std::make_unique<AnisotropicGradient<true>>(fit, std::move(plain));
  }
  NdfExportLobe export_lobe(const std::vector<double>& v) const override {
    NdfExportLobe e;
    e.alpha_x = v[0];
    e.alpha_y = v[1];
    e.phi = v[2];
    return e;
  }
  nlohmann::json params_json(const std::vector<double>& v) const override {
    return legacy_anisotropic_json(v);
  }
};

}  // namespace

std::unique_ptr<NdfModel> make_ggx_model() { return std::make_unique<GgxModel>(); }

}  // namespace microbrdf
