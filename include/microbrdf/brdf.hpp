#pragma once
// The BRDF interface and the microfacet BRDF (Dong 2015 eq. 1).
//
// Local frame (docs/architecture.md): macro normal n = +z, x and y in the surface; wi (light) and
// wo (viewer) both point away from the surface; f(wi, wo) in 1/sr; wavelength in metres.
//
// Slices (tabulate_slice): wi = (-sin theta_i, 0, cos theta_i), i.e. the light at azimuth 180 deg.
//  - in-plane:  wo(t) = (sin t, 0, cos t), t in [-90, 90] deg; the mirror direction is t =
//  +theta_i;
//  - out-of-plane: wo(t) = cos t r + sin t y with r = (sin theta_i, 0, cos theta_i) the mirror
//    direction, t in [-90, 90] deg (the great circle through r perpendicular to the plane of
//    incidence).

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "microbrdf/fresnel.hpp"
#include "microbrdf/microfacet.hpp"

namespace microbrdf {

struct BrdfSample {
  Vec3 wo;
  double weight = 0;  ///< f(wi, wo) cos(theta_o) / pdf
  double pdf = 0;     ///< per steradian of wo
};

class Brdf {
 public:
  virtual ~Brdf() = default;
  /// f(wi, wo) in 1/sr (0 when either direction is below the horizon).
  virtual double eval(const Vec3& wi, const Vec3& wo, double wavelength_m) const = 0;
  /// Draws wo for the light direction wi; nothing when the sample is absorbed/invalid.
  virtual std::optional<BrdfSample> sample(const Vec3& wi, double u1, double u2,
                                           double wavelength_m) const = 0;
  /// Density of sample() per steradian of wo.
  virtual double pdf(const Vec3& wi, const Vec3& wo) const = 0;
  virtual std::string describe() const = 0;
};

/// Dong 2015 eq. 1: f = F(wi.h) D(h) G(wi, wo) / (4 |wi.n| |wo.n|), h = (wi + wo)/|wi + wo|.
/// G is Smith's height-correlated G2 by default; `separable_g` gives G1(wi) G1(wo) (Dong eq. 13).
/// Sampling draws h with the distribution's sample_visible (the visible normals of wi for the
/// analytic models) and reflects: pdf = q(h) / (4 wi.h) with q = sampling_pdf(wi, h) (D_wi(h)
/// for visible normals, then weight = F G2 / G1u(wi)); weight = F D G2 (wi.h) / ((wi.n) q).
class MicrofacetBrdf final : public Brdf {
 public:
  MicrofacetBrdf(std::shared_ptr<const MicrofacetDistribution> d, std::shared_ptr<const Fresnel> f,
                 bool separable_g = false);
  double eval(const Vec3& wi, const Vec3& wo, double wavelength_m) const override;
  std::optional<BrdfSample> sample(const Vec3& wi, double u1, double u2,
                                   double wavelength_m) const override;
  double pdf(const Vec3& wi, const Vec3& wo) const override;
  std::string describe() const override;
  const MicrofacetDistribution& distribution() const { return *d_; }
  const Fresnel& fresnel() const { return *f_; }

 private:
  std::shared_ptr<const MicrofacetDistribution> d_;
  std::shared_ptr<const Fresnel> f_;
  bool separable_;
};

/// The reflection half vector h = (wi + wo)/|wi + wo| and wi.h, or nothing when either direction
/// is at or below the surface or wi.h <= 0. A half-vector density p(h) per steradian gives the
/// density of wo as p(h) / (4 wi.h).
struct HalfVector {
  Vec3 h;
  double wi_dot_h;
};
std::optional<HalfVector> reflection_half_vector(const Vec3& wi, const Vec3& wo);

/// Directional albedo a(wi) = integral f(wi, wo) cos(theta_o) dwo by product quadrature:
/// Gauss-Legendre in cos(theta_o) (n_theta nodes) times the midpoint rule in phi_o (n_phi).
/// Accurate for lobes wider than a few grid steps (alpha >~ 0.05 at the defaults).
double directional_albedo(const Brdf& brdf, const Vec3& wi, double wavelength_m, int n_theta = 128,
                          int n_phi = 256);
/// The same estimated with the BRDF's own sampler on an n x n stratified grid (any lobe width).
double directional_albedo_sampled(const Brdf& brdf, const Vec3& wi, double wavelength_m,
                                  int n = 512);

enum class SlicePlane { in, out };
struct BrdfSlice {
  std::vector<double> angle_deg;  ///< signed angle t of wo (see the header comment)
  std::vector<double> value;      ///< f, 1/sr
  std::vector<Vec3> wo;
};
/// Tabulates f along an in-plane or out-of-plane cut for light at theta_i (rad); `samples` angles
/// spread evenly over [-90, 90] deg (end points nudged 1e-9 rad inside the hemisphere).
BrdfSlice tabulate_slice(const Brdf& brdf, double theta_i, double wavelength_m, SlicePlane plane,
                         std::size_t samples = 721);

/// Gauss-Legendre nodes and weights on [-1, 1].
void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& w);

}  // namespace microbrdf
