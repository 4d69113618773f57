#pragma once
// The Student-t slope distribution (Ribardiere, Bringier, Meneveaux, Simonot 2017, "STD:
// Student's t-Distribution of Slopes for Microfacet Based BSDFs"): a microfacet NDF between GGX
// (gamma = 2) and Beckmann (gamma -> inf) whose extra parameter gamma sets the weight of the
// tails. Conventions as in microfacet.hpp (n = +z; alpha_x along the in-plane axis at azimuth
// phi, rad, counter-clockwise from +x).
//
// Slope density, in the frame turned by phi (slopes x, y dimensionless, gamma > 1):
//   P22(x, y) = (gamma - 1)^gamma / (pi ax ay) (gamma - 1 + x^2/ax^2 + y^2/ay^2)^-gamma
//             = (1 + (x^2/ax^2 + y^2/ay^2)/(gamma - 1))^-gamma / (pi ax ay)
//   D(m)      = P22(-mx/mz, -my/mz) / mz^4   (1/sr; integral D (m.n) dw = 1)
// Its tails fall like |slope|^(-2 gamma): the mean |slope| and with it sigma+(v) are finite only
// for gamma > 1.5 (docs/models.md, "Student-t NDF").

#include <cmath>
#include <memory>
#include <string>

#include "microbrdf/microfacet.hpp"

namespace microbrdf {

namespace student_t {
class Slopes;  // the 1-D slope statistics of one gamma (src/models/student_t_math.hpp)
}

/// P22 above, the slope density per unit slope^2, from the slopes (sx, sy) in the frame turned
/// by phi. A template so that a fit can use the same formula with its derivative type (e.g.
/// ceres::Jet): only arithmetic, exp and log1p, found by argument-dependent lookup.
template <class T>
T student_t_slope_density(const T& ax, const T& ay, const T& gamma, const T& sx, const T& sy) {
  using std::exp;
  using std::log1p;
  const T q = sx * sx / (ax * ax) + sy * sy / (ay * ay);
  // (1 + q/(gamma-1))^-gamma through log1p: exact to rounding for gamma up to 1e15 (-> e^-q).
  return exp(-gamma * log1p(q / (gamma - 1.0))) / (3.14159265358979323846 * ax * ay);
}

/// D(m) = P22(sx, sy) / cos^4(theta_m), 1/sr: the slopes sx = -x/mz, sy = -y/mz of the normal's
/// components (x, y) in the frame turned by phi, and cos_theta = mz > 0. The sign of the slopes
/// does not matter (P22 is even in each).
template <class T>
T student_t_d(const T& ax, const T& ay, const T& gamma, const T& sx, const T& sy,
              const T& cos_theta) {
  const T c2 = cos_theta * cos_theta;
  return student_t_slope_density(ax, ay, gamma, sx, sy) / (c2 * c2);
}

/// D(m) from a unit normal (mx, my, mz), mz > 0, and the azimuth phi (rad) of the alpha_x axis.
template <class T>
T student_t_d(const T& ax, const T& ay, const T& phi, const T& gamma, const T& mx, const T& my,
              const T& mz) {
  using std::cos;
  using std::sin;
  const T c = cos(phi), s = sin(phi);
  return student_t_d(ax, ay, gamma, (c * mx + s * my) / mz, (c * my - s * mx) / mz, mz);
}

/// Parameters of the Student-t NDF.
struct StudentTParams {
  double alpha_x = 0.1, alpha_y = 0.1;  ///< in (0, 10]; the slope scale, as for GGX/Beckmann
  double phi = 0;                       ///< azimuth of the alpha_x axis, rad
  double gamma = 2;                     ///< tail exponent in (1, 1e6]: 2 = GGX, -> inf Beckmann
};

/// Smallest and largest gamma the class accepts (the fit may bound it tighter).
inline constexpr double kStudentTGammaMin = 1.0;  ///< exclusive
inline constexpr double kStudentTGammaMax = 1e6;  ///< inclusive

/// The Student-t NDF with its exact Smith Lambda and exact visible-normal sampling.
///
/// - lambda(v): with mu = 1/(alpha_v tan theta_v) (alpha_v as for GGX) and a = gamma - 1,
///   Lambda = G(mu)/mu - S(mu): S the upper tail of the marginal slope density P2 (an incomplete
///   beta function, the paper's 2F1), G(mu) = sqrt(a) (1 + mu^2/a)^(1/2 - a) / ((2a - 1) B(a,
///   1/2)). Closed form (G1 agrees with quadrature of the Smith integral to 8e-12,
///   tests/test_student_t.cpp). gamma <= 1.5: +inf off the normal (G1 = 0), 0 at the normal.
/// - sample_visible(v, u1, u2): stretch the view to alpha = 1, draw the slope along its azimuth
///   from <mu - x>+ P2(x) by inverting the CDF numerically (error ~1e-11 (1 + |x|)), the slope
///   across it from its conditional Student-t (a quantile, same accuracy), turn back, unstretch:
///   the density is pdf_visible exactly. gamma <= 1.5 with v off the normal, where D_v does not
///   exist (sigma+ = inf): draws D(m)(m.n) instead, and sampling_pdf says so.
class StudentTDistribution final : public MicrofacetDistribution {
 public:
  /// Throws InputError for alphas outside (0, 10], gamma outside (1, 1e6] or non-finite values.
  explicit StudentTDistribution(const StudentTParams& p);
  StudentTDistribution(double alpha_x, double alpha_y, double phi, double gamma)
      : StudentTDistribution(StudentTParams{alpha_x, alpha_y, phi, gamma}) {}
  double D(const Vec3& m) const override;
  double lambda(const Vec3& v) const override;
  Vec3 sample_visible(const Vec3& v, double u1, double u2) const override;
  double sampling_pdf(const Vec3& v, const Vec3& m) const override;
  /// "student-t alpha=(ax, ay) phi=.. deg gamma=..".
  std::string describe() const override;
  /// Visible normals are drawn exactly where they exist (gamma > 1.5).
  bool samples_visible_exactly() const override { return p_.gamma > 1.5; }
  std::string model_name() const override { return "student-t"; }
  std::vector<double> model_values() const override {
    return {p_.alpha_x, p_.alpha_y, p_.phi, p_.gamma};
  }
  const StudentTParams& params() const { return p_; }

 private:
  StudentTParams p_;
  double c_, s_;  // cos phi, sin phi
  std::shared_ptr<const student_t::Slopes> slopes_;
};

}  // namespace microbrdf
