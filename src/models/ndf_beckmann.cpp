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

class BeckmannModel final : public AnisotropicModel<BeckmannUnit, false> {
 public:
  std::string name() const override { return "beckmann"; }
  std::string label() const override { return "Beckmann"; }
  std::string summary() const override {
    return "Beckmann (alpha_x, alpha_y, phi); Gaussian slopes, exact-erf Smith Lambda";
  }
  std::shared_ptr<MicrofacetDistribution> make(const std::vector<double>& v) const override {
    return std::make_shared<BeckmannDistribution>(v[0], v[1], v[2]);
  }
  // (export_lobe: the default, the exporters fit GGX to it.)
};

}  // namespace

std::unique_ptr<NdfModel> make_beckmann_model() { return std::make_unique<BeckmannModel>(); }

}  // namespace microbrdf
