#pragma once
// RGL `.bsdf` material files (Dupuy & Jakob 2018, "An Adaptive Parameterization for Efficient
// Material Acquisition and Rendering"): the tensor file of tensor_file.hpp with the fields
//   description (uint8 text), jacobian (uint8 [1]), theta_i, phi_i (float32, rad),
//   ndf, sigma (float32 [n_phi, n_theta]), vndf (float32 [n_phi_i, n_theta_i, n_phi, n_theta]),
//   luminance (float32 [n_phi_i, n_theta_i, n, n]),
//   spectra (float32 [n_phi_i, n_theta_i, n_wavelengths, n, n]) + wavelengths (float32, nm)
//   or rgb (float32 [n_phi_i, n_theta_i, 3, n, n]).
// RglBrdf reconstructs the BRDF the way Mitsuba 3's `measured` plugin and pbrt-v4's
// MeasuredBxDF do (docs/measured.md):
//   u(theta) = sqrt(2 theta / pi), u(phi) = (phi + pi) / (2 pi); m = (wi + wo)/|wi + wo|;
//   isotropic files (phi_i has <= 2 nodes) use phi_m - phi_i;
//   s = vndf.invert(u(m); phi_i, theta_i);  R(lambda) = spectra(s; phi_i, theta_i, lambda);
//   f(wi, wo) cos(theta_o) = R ndf(u(m)) / (4 sigma(u(wi)))   (jacobian = 1; R alone if 0);
//   sampling: luminance warp, then the vndf warp, reflect; pdf(wo) = p_lum(s) p_vndf(u(m)) /
//   (2 pi^2 u_theta(m) sin(theta_m) 4 (wi.m)).
// RGB files map channels to the wavelengths of merl_channel_wavelengths().

#include <memory>
#include <string>

#include "microbrdf/brdf.hpp"
#include "microbrdf/tensor_file.hpp"

namespace microbrdf {

class RglBrdf final : public Brdf {
 public:
  /// Checks every field's dtype, rank and shape (as the renderers do) and that every
  /// sampling slice has positive mass. Throws FileError(path, ...).
  RglBrdf(const TensorFile& file, const std::string& path);
  static RglBrdf load(const std::string& path);
  ~RglBrdf() override;
  RglBrdf(RglBrdf&&) noexcept;

  double eval(const Vec3& wi, const Vec3& wo, double wavelength_m) const override;
  std::optional<BrdfSample> sample(const Vec3& wi, double u1, double u2,
                                   double wavelength_m) const override;
  double pdf(const Vec3& wi, const Vec3& wo) const override;
  std::string describe() const override;

  bool isotropic() const;
  const std::string& description() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> p_;
};

}  // namespace microbrdf
