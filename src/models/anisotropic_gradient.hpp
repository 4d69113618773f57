#pragma once
// The hand-written gradient of the Beckmann and GGX D with respect to their fit-space
// parameters (log alpha_x, log alpha_y, phi): the fits' fast path. The reference is the
// automatic derivative of the same D template (microfacet_lobes.hpp); tests compare the two.
#include <cmath>
#include <memory>

#include "microbrdf/ndf_model.hpp"
#include "microbrdf/ndf_model_template.hpp"
#include "models/ndf_builtin.hpp"

namespace microbrdf {

template <bool Ggx>
class AnisotropicGradient final : public NdfEvaluator {
 public:
  /// `plain`: the template's evaluator, used for rows without derivatives.
  AnisotropicGradient(const double* fit, std::unique_ptr<NdfEvaluator> plain)
      : plain_(std::move(plain)) {
    constexpr double kPi = 3.14159265358979323846;
    const double ax = std::exp(fit[0]), ay = std::exp(fit[1]);
    iax2_ = 1 / (ax * ax);
    iay2_ = 1 / (ay * ay);
    c_ = std::cos(fit[2]);
    s_ = std::sin(fit[2]);
    norm_ = 1 / (kPi * ax * ay);
  }
  void row(double x0, double h, std::size_t n, double y, double* val, double* grad,
           std::size_t stride) const override {
    if (!grad) return plain_->row(x0, h, n, y, val, grad, stride);
    for (std::size_t i = 0; i < n; ++i) {
      const double x = x0 + static_cast<double>(i) * h, r2 = x * x + y * y;
      double g[3] = {0, 0, 0}, d = 0;
      if (r2 < 1) d = eval(x, y, std::sqrt(1 - r2), g);
      val[i] = d;
      for (std::size_t p = 0; p < 3; ++p) grad[p * stride + i] = g[p];
    }
  }

 private:
  double eval(double x, double y, double z, double* g) const {
    const double u = c_ * x + s_ * y, v = -s_ * x + c_ * y;
    const double uu = u * u * iax2_, vv = v * v * iay2_, uv = u * v * (iay2_ - iax2_);
    if constexpr (Ggx) {
      const double q = uu + vv + z * z;
      const double d = norm_ / (q * q), iq = 1 / q;
      g[0] = d * (4 * uu * iq - 1);
      g[1] = d * (4 * vv * iq - 1);
      g[2] = 4 * d * uv * iq;
      return d;
    }
    const double z2 = z * z, iz2 = 1 / z2;
    const double d = norm_ * std::exp(-(uu + vv) * iz2) / (z2 * z2);
    g[0] = d * (2 * uu * iz2 - 1);
    g[1] = d * (2 * vv * iz2 - 1);
    g[2] = 2 * d * uv * iz2;
    return d;
  }
  std::unique_ptr<NdfEvaluator> plain_;
  double c_ = 1, s_ = 0, iax2_ = 1, iay2_ = 1, norm_ = 1;
};

/// What Beckmann and GGX share as registry entries: parameters (alpha_x, alpha_y, phi), the
/// hand-written gradient as the fits' fast path, the legacy JSON keys.
template <class Unit, bool Ggx>
class AnisotropicModel : public TemplateNdfModel<Unit> {
 public:
  const std::vector<NdfParam>& params() const override { return anisotropic_params(); }
  std::unique_ptr<NdfEvaluator> evaluator(const double* fit, bool reference) const override {
    auto plain = TemplateNdfModel<Unit>::evaluator(fit, true);
    if (reference) return plain;
    return std::make_unique<AnisotropicGradient<Ggx>>(fit, std::move(plain));
  }
  nlohmann::json params_json(const std::vector<double>& v) const override {
    return legacy_anisotropic_json(v);
  }
};

}  // namespace microbrdf
