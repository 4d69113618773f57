// Spectral evaluation of materials (see material.hpp).
#include "render/material.hpp"

#include <cmath>
#include <string>

namespace microbrdf::pt {

SpectralMaterial::SpectralMaterial(std::shared_ptr<const Svbrdf> m) : m_(std::move(m)) {
  const auto* u = dynamic_cast<const UniformSvbrdf*>(m_.get());
  mf_ = u ? dynamic_cast<const MicrofacetBrdf*>(&u->brdf()) : nullptr;
  if (!mf_) return;
  separable_ = mf_->describe().find("separable Smith") != std::string::npos;
  // Self-check against the BRDF's own eval (light and view on a small spiral of directions).
  for (int i = 0; i < 16 && mf_; ++i) {
    const double ti = 0.1 + 0.09 * i, pi = 0.7 * i, to = 1.4 - 0.08 * i, po = 2.9 + 0.3 * i;
    const Vec3 wi(std::sin(ti) * std::cos(pi), std::sin(ti) * std::sin(pi), std::cos(ti));
    const Vec3 wo(std::sin(to) * std::cos(po), std::sin(to) * std::sin(po), std::cos(to));
    const double lambda = 555e-9;
    double fast;
    eval(0, 0, wi, wo, &lambda, 1, &fast);
    const double ref = mf_->eval(wi, wo, lambda);
    if (!(std::abs(fast - ref) <= 1e-12 * std::abs(ref) + 1e-300)) mf_ = nullptr;
  }
}

void SpectralMaterial::eval(double u, double v, const Vec3& wi, const Vec3& wo,
                            const double* lambda_m, int n, double* f) const {
  if (!mf_) {
    for (int k = 0; k < n; ++k) f[k] = m_->eval(u, v, wi, wo, lambda_m[k]);
    return;
  }
  for (int k = 0; k < n; ++k) f[k] = 0;
  if (wi.z() <= 0 || wo.z() <= 0) return;
  const Vec3 hs = wi + wo;
  const double len = hs.norm();
  if (len == 0) return;
  const Vec3 h = hs / len;
  const double g = mf_->distribution().G2(wi, wo, h, separable_);
  if (g == 0) return;
  const double geo = mf_->distribution().D(h) * g / (4 * wi.z() * wo.z());
  if (geo == 0) return;
  const double c = wi.dot(h);
  for (int k = 0; k < n; ++k) f[k] = mf_->fresnel().eval(c, lambda_m[k]) * geo;
}

}  // namespace microbrdf::pt
