#pragma once
// A material as the path tracer uses it: an Svbrdf evaluated at all hero wavelengths of a path
// at once. For a uniform microfacet BRDF (UniformSvbrdf around a MicrofacetBrdf) the
// wavelength-independent factor D(h) G2 / (4 cos_i cos_o) is computed once and only the Fresnel
// term per wavelength (the same formula as MicrofacetBrdf::eval); any other Svbrdf is evaluated
// wavelength by wavelength. MicrofacetBrdf has no accessor for its G2 choice: it is read from
// describe(), and the fast path is checked against eval() on a few direction pairs at
// construction (and dropped if they differ).

#include <memory>

#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/svbrdf.hpp"

namespace microbrdf::pt {

class SpectralMaterial {
 public:
  explicit SpectralMaterial(std::shared_ptr<const Svbrdf> m);
  /// f(wi, wo) at n wavelengths (metres) into f; wi = light, wo = viewer (local frame).
  void eval(double u, double v, const Vec3& wi, const Vec3& wo, const double* lambda_m, int n,
            double* f) const;
  const Svbrdf& svbrdf() const { return *m_; }
  /// Whether the microfacet fast path is in use.
  bool fast() const { return mf_ != nullptr; }

 private:
  std::shared_ptr<const Svbrdf> m_;
  const MicrofacetBrdf* mf_ = nullptr;
  bool separable_ = false;
};

}  // namespace microbrdf::pt
