#pragma once
// The BRDF interface every reflectance model of the project implements.
//
// Local frame (docs/architecture.md): macro normal n = +z, x and y in the surface; wi (light) and
// wo (viewer) both point away from the surface; f(wi, wo) in 1/sr; wavelength in metres. The BRDFs
// themselves: microfacet_brdf.hpp (Dong 2015 eq. 1), kirchhoff_brdf.hpp (eq. 8), sun_brdf.hpp (Sun
// 2002), sh_brdf.hpp (Westin 1992), lambertian_brdf.hpp, mirror_brdf.hpp; the one way to build any
// of them from a description: brdf_spec.hpp.

#include <optional>
#include <string>

#include "microbrdf/vec3.hpp"

namespace microbrdf {

/// The kinds of reflection a BRDF has; a renderer chooses its estimators by them (a delta lobe
/// has no density: it is only reached by sampling, never by light sampling or MIS).
struct Lobes {
  bool delta = false;    ///< ideal specular: f is a Dirac delta (eval() and pdf() are 0)
  bool glossy = false;   ///< a lobe of finite width around a preferred direction
  bool diffuse = false;  ///< spread over the whole hemisphere
};

struct BrdfSample {
  Vec3 wo;
  double weight = 0;   ///< f(wi, wo) cos(theta_o) / pdf (for a delta lobe: the reflectance)
  double pdf = 0;      ///< per steradian of wo (0 for a delta lobe)
  bool delta = false;  ///< drawn from a delta lobe
};

class Brdf {
 public:
  virtual ~Brdf() = default;
  /// f(wi, wo) in 1/sr (0 when either direction is below the horizon).
  virtual double eval(const Vec3& wi, const Vec3& wo, double wavelength_m) const = 0;
  /// f(wi, wo) at n wavelengths (m) into f[0..n-1], each equal to eval() at that wavelength.
  /// BRDFs whose cost does not depend on the wavelength (a random walk that only its Fresnel
  /// factors see) override it to do that work once.
  virtual void eval_spectral(const Vec3& wi, const Vec3& wo, const double* wavelengths_m, int n,
                             double* f) const {
    for (int k = 0; k < n; ++k) f[k] = eval(wi, wo, wavelengths_m[k]);
  }
  /// Draws wo for the light direction wi; nothing when the sample is absorbed/invalid.
  virtual std::optional<BrdfSample> sample(const Vec3& wi, double u1, double u2,
                                           double wavelength_m) const = 0;
  /// Density of sample() per steradian of wo (0 for the delta part).
  virtual double pdf(const Vec3& wi, const Vec3& wo) const = 0;
  /// Directional albedo a(wi) = integral f(wi, wo) cos(theta_o) dwo (dimensionless). By default
  /// estimated with the BRDF's own sampler on a 256 x 256 stratified grid
  /// (directional_albedo_sampled, brdf_albedo.hpp); BRDFs with an exact integral override it.
  virtual double albedo(const Vec3& wi, double wavelength_m) const;
  /// Which lobes the BRDF has (default: glossy).
  virtual Lobes lobes() const { return {false, true, false}; }
  virtual std::string describe() const = 0;
};

/// The reflection half vector h = (wi + wo)/|wi + wo| and wi.h, or nothing when either direction
/// is at or below the surface or wi.h <= 0. A half-vector density p(h) per steradian gives the
/// density of wo as p(h) / (4 wi.h).
struct HalfVector {
  Vec3 h;
  double wi_dot_h;
};
std::optional<HalfVector> reflection_half_vector(const Vec3& wi, const Vec3& wo);

}  // namespace microbrdf
