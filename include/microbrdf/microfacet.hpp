#pragma once
// Microfacet normal distributions (NDFs) with Smith shadowing and visible-normal sampling.
//
// Local frame: macro normal n = +z; every direction points away from the surface. D(m) is per
// steradian, normalised so that integral D(m) (m.n) dw_m = 1 over the hemisphere.
//   sigma+(v) = integral D(m) <v.m>+ dw_m         projected area of the microsurface seen from v
//   Lambda(v) = sigma+(v) / (v.n) - 1             Smith (docs/theory.md §1.4, 2.3; Heitz 2014)
//   G1(v, m)  = chi+((v.m)/(v.n)) min(1, 1/(1 + Lambda(v)))
//   D_v(m)    = <v.m>+ D(m) / sigma+(v) = G1u(v) <v.m>+ D(m) / (v.n)   (visible normals; G1u the
//               unclamped Smith term, which is the exact normaliser even when G1 > 1)
// sample_visible(v, u1, u2) draws m with density sampling_pdf(v, m) per steradian exactly: D_v(m)
// for Beckmann, GGX and the ellipsoid; D(m)(m.n) (not the visible normals) for a tabulated NDF
// (tabulated_distribution.hpp). Code that weights samples (MicrofacetBrdf) uses sampling_pdf.
//
// Anisotropy: alpha_x along the in-plane axis at azimuth `phi` (rad, counter-clockwise from +x),
// alpha_y perpendicular to it. The ellipsoid NDF is Dong et al. 2015 eqs. 10-14; see
// docs/models.md and docs/theory.md §1 for its conventions.

#include <Eigen/Core>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "microbrdf/tabulated_ndf.hpp"
#include "microbrdf/vec3.hpp"

namespace microbrdf {

class MicrofacetDistribution {
 public:
  virtual ~MicrofacetDistribution() = default;

  /// D(m), 1/sr; m must be a unit vector. 0 for m.z <= 0.
  virtual double D(const Vec3& m) const = 0;
  /// Smith Lambda(v) for a unit v with v.z > 0 (unclamped; may be < 0 for the skewed ellipsoid).
  virtual double lambda(const Vec3& v) const = 0;
  /// Draws a normal for the view v (v.z > 0) from two uniforms in [0,1), with density
  /// sampling_pdf(v, m): the visible normals D_v for the analytic models.
  virtual Vec3 sample_visible(const Vec3& v, double u1, double u2) const = 0;
  /// Density per steradian of sample_visible(v, ...): pdf_visible(v, m) unless overridden.
  virtual double sampling_pdf(const Vec3& v, const Vec3& m) const { return pdf_visible(v, m); }
  /// True when sample_visible draws the visible normals D_v exactly (sampling_pdf = pdf_visible,
  /// which renderers then evaluate in closed form); false for samplers of another density.
  virtual bool samples_visible_exactly() const { return true; }
  /// The registered model (ndf_model.hpp) and the values that make this distribution, so that
  /// exporters and reports can ask the model; "" and {} for distributions outside the registry.
  virtual std::string model_name() const { return ""; }
  virtual std::vector<double> model_values() const { return {}; }
  /// Short description for reports ("ggx alpha=(0.1, 0.2) phi=0").
  virtual std::string describe() const = 0;

  /// sigma+(v) = (v.n)(1 + Lambda(v)); 0 for v.z <= 0.
  double projected_area(const Vec3& v) const { return v.z() > 0 ? v.z() * (1.0 + lambda(v)) : 0.0; }
  /// Smith G1(v) = min(1, 1/(1 + Lambda(v))) for v.z > 0, else 0.
  double G1(const Vec3& v) const;
  /// G1(v, m) with the sidedness test chi+((v.m)/(v.n)).
  double G1(const Vec3& v, const Vec3& m) const;
  /// Height-correlated Smith G2 = 1/(1 + Lambda(wi) + Lambda(wo)) with the sidedness tests, Lambda
  /// clamped to >= 0 (only the skewed ellipsoid has Lambda < 0, i.e. G1 > 1 before eq. 14's clamp);
  /// `separable` gives G1(wi, m) G1(wo, m) (Dong eq. 13) instead.
  double G2(const Vec3& wi, const Vec3& wo, const Vec3& m, bool separable = false) const;
  /// D_v(m) per steradian (the density of sample_visible for the analytic models).
  double pdf_visible(const Vec3& v, const Vec3& m) const;
  /// Draws m with density D(m)(m.n) (the visible normals for v = n; every model samples this
  /// density exactly for v = n).
  Vec3 sample(double u1, double u2) const { return sample_visible(Vec3(0, 0, 1), u1, u2); }
  /// Density of sample(): D(m)(m.n).
  double pdf(const Vec3& m) const { return m.z() > 0 ? D(m) * m.z() : 0.0; }
};

/// Common parameters of the two mirror-symmetric anisotropic models.
struct AnisotropicAlpha {
  double alpha_x = 0.1, alpha_y = 0.1;
  double phi = 0;  ///< azimuth of the alpha_x axis, rad
};

/// Beckmann: D = exp(-(x^2/ax^2 + y^2/ay^2)/z^2) / (pi ax ay z^4) in the rotated frame; exact
/// Smith Lambda = (erf(a) - 1)/2 + exp(-a^2)/(2 a sqrt(pi)), a = 1/(alpha_v tan theta_v) (returned
/// as 0 for a > 5.75, where Lambda < 4e-18 and 1 + Lambda rounds to 1); visible-normal sampling by
/// inverting the visible-slope CDF to 1e-10 of the slope (Halley on erfc from a tabulated start;
/// docs/models.md) and the perpendicular slope by an erfinv accurate to ~1e-15.
class BeckmannDistribution final : public MicrofacetDistribution {
 public:
  BeckmannDistribution(double alpha_x, double alpha_y, double phi = 0);
  explicit BeckmannDistribution(double alpha) : BeckmannDistribution(alpha, alpha, 0) {}
  double D(const Vec3& m) const override;
  double lambda(const Vec3& v) const override;
  Vec3 sample_visible(const Vec3& v, double u1, double u2) const override;
  std::string describe() const override;
  std::string model_name() const override { return "beckmann"; }
  std::vector<double> model_values() const override { return {p_.alpha_x, p_.alpha_y, p_.phi}; }
  const AnisotropicAlpha& params() const { return p_; }

 private:
  AnisotropicAlpha p_;
  double c_, s_;              // cos phi, sin phi
  double inv_ax2_, inv_ay2_;  // 1/alpha^2
  double d_norm_;             // 1/(pi alpha_x alpha_y)
};

/// GGX / Trowbridge-Reitz (= Burley's GTR2aniso): D = 1/(pi ax ay (x^2/ax^2 + y^2/ay^2 + z^2)^2);
/// Lambda = (sqrt(1 + alpha_v^2 tan^2 theta_v) - 1)/2; Heitz 2018 visible-normal sampling.
class GgxDistribution final : public MicrofacetDistribution {
 public:
  GgxDistribution(double alpha_x, double alpha_y, double phi = 0);
  explicit GgxDistribution(double alpha) : GgxDistribution(alpha, alpha, 0) {}
  double D(const Vec3& m) const override;
  double lambda(const Vec3& v) const override;
  Vec3 sample_visible(const Vec3& v, double u1, double u2) const override;
  std::string describe() const override;
  std::string model_name() const override { return "ggx"; }
  std::vector<double> model_values() const override { return {p_.alpha_x, p_.alpha_y, p_.phi}; }
  const AnisotropicAlpha& params() const { return p_; }

 private:
  AnisotropicAlpha p_;
  double c_, s_;
};

/// Parameters of the ellipsoid NDF (Dong 2015 eqs. 11-12): A = S R, S = diag(alpha_x, alpha_y, 1),
/// R = Rx(theta_x) Ry(theta_y) Rz(theta_z), active right-handed rotations (Rx(t) turns +y towards
/// +z). The peak lies at m* = R^T z (for alpha < 1): theta_x, theta_y tilt it, theta_z turns the
/// anisotropy axes about n by -theta_z (so R = Rz(theta_z) equals GGX with phi = -theta_z).
struct EllipsoidParams {
  double alpha_x = 0.1, alpha_y = 0.1;
  double theta_x = 0, theta_y = 0, theta_z = 0;  ///< rad
};

/// Dong 2015 eq. 10: D(m) = chi+(m.n) / (pi |det A| ||A n|| ||A^-T m||^4); eq. 14 G1 via
/// sigma+(u) = ||Au||/(2||An||) + (Au).(An)/(2||An||^2) (docs/theory.md §1.4); visible normals
/// sampled on the ellipsoid mapped to the unit sphere (docs/theory.md §1.5), exact pdf D_v.
class EllipsoidDistribution final : public MicrofacetDistribution {
 public:
  explicit EllipsoidDistribution(const EllipsoidParams& p);
  double D(const Vec3& m) const override;
  double lambda(const Vec3& v) const override;
  Vec3 sample_visible(const Vec3& v, double u1, double u2) const override;
  std::string describe() const override;
  std::string model_name() const override { return "ellipsoid"; }
  std::vector<double> model_values() const override {
    return {p_.alpha_x, p_.alpha_y, p_.theta_x, p_.theta_y, p_.theta_z};
  }
  const EllipsoidParams& params() const { return p_; }
  const Eigen::Matrix3d& A() const { return a_; }
  const Eigen::Matrix3d& R() const { return r_; }
  /// The direction of the maximum of D (for alpha_x, alpha_y < 1): R^T z, flipped up if needed.
  Vec3 peak() const;
  /// integral D(m) m dw = A^T A n / ||A n||^2 (docs/theory.md §1.2), the mean normal (not unit
  /// length).
  Vec3 mean_normal() const;

 private:
  EllipsoidParams p_;
  Eigen::Matrix3d r_, a_, ainvt_;
  Vec3 an_;  // A n
  double an_norm_, det_;
  Vec3 np_, b1_, b2_;  // sample_visible's frame: n' = An/|An| and two unit vectors across it
};

/// What the CLI and file formats use to name a distribution.
struct NdfSpec {
  std::string model = "ggx";  ///< a registered model (ndf_model.hpp): "beckmann", "ggx", ...
  double alpha_x = 0.1, alpha_y = 0.1;
  double phi = 0;                                ///< beckmann/ggx: azimuth of the alpha_x axis, rad
  double theta_x = 0, theta_y = 0, theta_z = 0;  ///< ellipsoid rotation angles, rad
  /// The other parameters of the model that were given (e.g. "gamma"), by name; the rest take
  /// the model's defaults.
  std::map<std::string, double> extra;
};
/// Builds the distribution through the model registry (ndf_model.hpp); throws InputError for an
/// unknown model, values outside the model's range, rotation angles given to a model that has
/// none, phi given to the ellipsoid (use theta_z), or a parameter of another model.
std::shared_ptr<MicrofacetDistribution> make_distribution(const NdfSpec& spec);

/// D(m) at every node of an N x N TabulatedNdf (orthographic disk, node-centred; 0 on and outside
/// the rim), then normalised to sum D Delta^2 = 1. meta.method = the model name, meta.notes = the
/// parameters and the sum before normalising (far from 1 when the lobe is narrower than a few
/// nodes: alpha <~ 3 Delta = 6/(N-1)); meta.sampling = "point". `window`: the nodes cover that
/// square of the disk plane only (a zoomed table, D = 0 outside it).
TabulatedNdf tabulate(const MicrofacetDistribution& d, const std::string& model,
                      std::size_t resolution = 1025, const NdfWindow& window = {});

/// Rotation matrices (active, right-handed).
Eigen::Matrix3d rotation_x(double t);
Eigen::Matrix3d rotation_y(double t);
Eigen::Matrix3d rotation_z(double t);

}  // namespace microbrdf
