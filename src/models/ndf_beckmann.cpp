// Beckmann as a registry entry (ndf_model.hpp): D in microfacet_lobes.hpp, the exact-erf Lambda
// and visible-normal sampling in BeckmannDistribution (microfacet.cpp).
#include "microbrdf/ndf_model_template.hpp"
#include "models/anisotropic_gradient.hpp"
#include "models/microfacet_lobes.hpp"
#include "models/ndf_builtin.hpp"

namespace microbrdf {
namespace {

struct BeckmannUnit {
  static constexpr int kParams = 3;
  template <typename T>
  using Lobe = lobes::Beckmann<T>;
};

class BeckmannModel final : public TemplateNdfModel<BeckmannUnit> {
 public:
  std::string name() const override { return "beckmann"; }
  std::string label() const override { return "Beckmann"; }
  std::string summary() const override {
    return "Beckmann (alpha_x, alpha_y, phi); Gaussian slopes, exact-erf Smith Lambda";
  }
  const std::vector<NdfParam>& params() const override { return anisotropic_params(); }
  std::shared_ptr<MicrofacetDistribution> make(const std::vector<double>& v) const override {
    return std::make_shared<BeckmannDistribution>(v[0], v[1], v[2]);
  }
  std::unique_ptr<NdfEvaluator> evaluator(const double* fit, bool reference) const override {
    auto plain = TemplateNdfModel<BeckmannUnit>::evaluator(fit, true);
    if (reference) return plain;
    return std::make_unique<AnisotropicGradient<false>>(fit, std::move(plain));
  }
  NdfExportLobe export_lobe(const std::vector<double>& v) const override {
    NdfExportLobe e;
    e.exact = false;  // the exporters fit GGX to it
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

std::unique_ptr<NdfModel> make_beckmann_model() { return std::make_unique<BeckmannModel>(); }

}  // namespace microbrdf
