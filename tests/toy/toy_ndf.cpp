// The toy model (toy_ndf.hpp): its D as a template (the fit differentiates it), its parameter,
// its distribution (Smith Lambda and visible-normal sampling of isotropic GGX).
#include "toy/toy_ndf.hpp"

#include <cmath>

#include "microbrdf/ndf_model_template.hpp"

namespace microbrdf::toy {
namespace {

struct ToyUnit {
  static constexpr int kParams = 1;
  template <typename T>
  struct Lobe {
    T r2;
    explicit Lobe(const T* v) : r2(v[0] * v[0]) {}
    T D(double x, double y, double z) const {
      const T q = T(x * x + y * y) / r2 + T(z * z);
      return T(1) / (T(3.14159265358979323846) * r2 * q * q);
    }
  };
};

class ToyModel final : public TemplateNdfModel<ToyUnit> {
 public:
  std::string name() const override { return "toy"; }
  std::string summary() const override { return "toy: isotropic GGX (roughness)"; }
  const std::vector<NdfParam>& params() const override {
    static const std::vector<NdfParam> p = {
        {"roughness", "1", "Roughness of the toy model", NdfParam::Kind::Alpha, 0, 10, 0.1}};
    return p;
  }
  std::shared_ptr<MicrofacetDistribution> make(const std::vector<double>& v) const override {
    return std::make_shared<GgxDistribution>(v[0], v[0], 0);
  }
  std::vector<double> initial(const NdfMoments& m) const override {
    return {std::sqrt(m.alpha_x * m.alpha_y)};
  }
};

}  // namespace

std::unique_ptr<NdfModel> make_toy_model() { return std::make_unique<ToyModel>(); }

}  // namespace microbrdf::toy
