#pragma once
// Spatially varying BRDFs: the interface the renderer draws with.
//
// Texture coordinates (u, v) are dimensionless, one unit = one texture repeat (the texture wraps);
// the local frame, directions and units are those of Brdf (brdf.hpp): n = +z, x = the texture's u
// axis (for brushed metals: the brushing direction of the exemplar scans, as the texture reports),
// wi and wo point away from the surface, f in 1/sr, wavelength in metres.

#include <memory>
#include <optional>
#include <string>

#include "microbrdf/brdf.hpp"

namespace microbrdf {

class Svbrdf {
 public:
  virtual ~Svbrdf() = default;
  /// f(wi, wo) at texture coordinate (u, v), in 1/sr.
  virtual double eval(double u, double v, const Vec3& wi, const Vec3& wo,
                      double wavelength_m) const = 0;
  /// f at n wavelengths (m) into f[0..n-1], each equal to eval() there (Brdf::eval_spectral).
  virtual void eval_spectral(double u, double v, const Vec3& wi, const Vec3& wo,
                             const double* wavelengths_m, int n, double* f) const {
    for (int k = 0; k < n; ++k) f[k] = eval(u, v, wi, wo, wavelengths_m[k]);
  }
  /// Draws wo for the light direction wi at (u, v) (see Brdf::sample).
  virtual std::optional<BrdfSample> sample(double u, double v, const Vec3& wi, double u1, double u2,
                                           double wavelength_m) const = 0;
  /// Density of sample() per steradian of wo.
  virtual double pdf(double u, double v, const Vec3& wi, const Vec3& wo) const = 0;
  virtual std::string describe() const = 0;
};

/// The same BRDF everywhere: lets any Brdf of the project go where an Svbrdf is expected.
class UniformSvbrdf final : public Svbrdf {
 public:
  explicit UniformSvbrdf(std::shared_ptr<const Brdf> brdf) : brdf_(std::move(brdf)) {}
  double eval(double, double, const Vec3& wi, const Vec3& wo, double wavelength_m) const override {
    return brdf_->eval(wi, wo, wavelength_m);
  }
  void eval_spectral(double, double, const Vec3& wi, const Vec3& wo, const double* wavelengths_m,
                     int n, double* f) const override {
    brdf_->eval_spectral(wi, wo, wavelengths_m, n, f);
  }
  std::optional<BrdfSample> sample(double, double, const Vec3& wi, double u1, double u2,
                                   double wavelength_m) const override {
    return brdf_->sample(wi, u1, u2, wavelength_m);
  }
  double pdf(double, double, const Vec3& wi, const Vec3& wo) const override {
    return brdf_->pdf(wi, wo);
  }
  std::string describe() const override { return brdf_->describe(); }
  const Brdf& brdf() const { return *brdf_; }

 private:
  std::shared_ptr<const Brdf> brdf_;
};

}  // namespace microbrdf
