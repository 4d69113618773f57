// The ellipsoid NDF (Dong 2015 eqs. 10-14) as a registry entry (ndf_model.hpp): D in
// microfacet_lobes.hpp, G1 and visible-normal sampling in EllipsoidDistribution.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "microbrdf/ndf_model_template.hpp"
#include "models/microfacet_lobes.hpp"
#include "models/ndf_builtin.hpp"

namespace microbrdf {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kMaxTilt = 1e300;  // the fits bound tilts themselves (NdfParam::Kind::Tilt)

struct EllipsoidUnit {
  static constexpr int kParams = 5;
  template <typename T>
  using Lobe = lobes::Ellipsoid<T>;
};

// D and its derivatives with respect to (log alpha_x, log alpha_y, theta_x, theta_y, theta_z)
// in closed form: the fits' fast path (the template's automatic derivatives are the reference).
class EllipsoidGradient final : public NdfEvaluator {
 public:
  EllipsoidGradient(const double* s, std::unique_ptr<NdfEvaluator> plain)
      : plain_(std::move(plain)) {
    const double ax = std::exp(s[0]), ay = std::exp(s[1]);
    const double cx = std::cos(s[2]), sx = std::sin(s[2]), cy = std::cos(s[3]), sy = std::sin(s[3]),
                 cz = std::cos(s[4]), sz = std::sin(s[4]);
    const double r[3][3] = {{cy * cz, -cy * sz, sy},
                            {sx * sy * cz + cx * sz, -sx * sy * sz + cx * cz, -sx * cy},
                            {-cx * sy * cz + sx * sz, cx * sy * sz + sx * cz, cx * cy}};
    const double dr[3][3][3] = {// d/d theta_x
                                {{0, 0, 0},
                                 {cx * sy * cz - sx * sz, -cx * sy * sz - sx * cz, -cx * cy},
                                 {sx * sy * cz + cx * sz, -sx * sy * sz + cx * cz, -sx * cy}},
                                // d/d theta_y
                                {{-sy * cz, sy * sz, cy},
                                 {sx * cy * cz, -sx * cy * sz, sx * sy},
                                 {-cx * cy * cz, cx * cy * sz, -cx * sy}},
                                // d/d theta_z
                                {{-cy * sz, -cy * cz, 0},
                                 {-sx * sy * sz + cx * cz, -sx * sy * cz - cx * sz, 0},
                                 {cx * sy * sz + sx * cz, cx * sy * cz - sx * sz, 0}}};
    const double sc[3] = {1 / ax, 1 / ay, 1};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        m_[i][j] = r[i][j] * sc[i];
        for (int t = 0; t < 3; ++t) dm_[t][i][j] = dr[t][i][j] * sc[i];
      }
    const double an2 =
        ax * ax * r[0][2] * r[0][2] + ay * ay * r[1][2] * r[1][2] + r[2][2] * r[2][2];
    norm_ = 1 / (kPi * ax * ay * std::sqrt(an2));
    dln_[0] = -1 - ax * ax * r[0][2] * r[0][2] / an2;
    dln_[1] = -1 - ay * ay * r[1][2] * r[1][2] / an2;
    for (int t = 0; t < 3; ++t)
      dln_[2 + t] = -(ax * ax * r[0][2] * dr[t][0][2] + ay * ay * r[1][2] * dr[t][1][2] +
                      r[2][2] * dr[t][2][2]) /
                    an2;
  }
  void row(double x0, double h, std::size_t n, double y, double* val, double* grad,
           std::size_t stride) const override {
    if (!grad) return plain_->row(x0, h, n, y, val, grad, stride);
    for (std::size_t i = 0; i < n; ++i) {
      const double x = x0 + static_cast<double>(i) * h, r2 = x * x + y * y;
      double g[5] = {0, 0, 0, 0, 0}, d = 0;
      if (r2 < 1) d = eval(x, y, std::sqrt(1 - r2), g);
      val[i] = d;
      for (std::size_t p = 0; p < 5; ++p) grad[p * stride + i] = g[p];
    }
  }

 private:
  double eval(double x, double y, double z, double* g) const {
    const double a = m_[0][0] * x + m_[0][1] * y + m_[0][2] * z;
    const double b = m_[1][0] * x + m_[1][1] * y + m_[1][2] * z;
    const double c = m_[2][0] * x + m_[2][1] * y + m_[2][2] * z;
    const double q = a * a + b * b + c * c;
    const double d = norm_ / (q * q), iq = 1 / q;
    g[0] = d * (dln_[0] + 4 * a * a * iq);
    g[1] = d * (dln_[1] + 4 * b * b * iq);
    for (int t = 0; t < 3; ++t) {
      const double da = dm_[t][0][0] * x + dm_[t][0][1] * y + dm_[t][0][2] * z;
      const double db = dm_[t][1][0] * x + dm_[t][1][1] * y + dm_[t][1][2] * z;
      const double dc = dm_[t][2][0] * x + dm_[t][2][1] * y + dm_[t][2][2] * z;
      g[2 + t] = d * (dln_[2 + t] - 4 * (a * da + b * db + c * dc) * iq);
    }
    return d;
  }
  std::unique_ptr<NdfEvaluator> plain_;
  double m_[3][3] = {}, dm_[3][3][3] = {}, norm_ = 0, dln_[5] = {};
};

class EllipsoidModel final : public TemplateNdfModel<EllipsoidUnit> {
 public:
  std::string name() const override { return "ellipsoid"; }
  std::string summary() const override {
    return "ellipsoid NDF (alpha_x, alpha_y, theta_x, theta_y, theta_z); Dong 2015 eqs. 10-14";
  }
  const std::vector<NdfParam>& params() const override {
    static const std::vector<NdfParam> p = {
        {"alpha_x", "1", "Roughness along the first axis", NdfParam::Kind::Alpha, 0, 10, 0.1},
        {"alpha_y", "1", "Roughness along the second axis", NdfParam::Kind::Alpha, 0, 10, 0.1},
        {"theta_x", "rad", "Rotation Rx, tilts the peak towards +y", NdfParam::Kind::Tilt,
         -kMaxTilt, kMaxTilt, 0},
        {"theta_y", "rad", "Rotation Ry, tilts the peak towards -x", NdfParam::Kind::Tilt,
         -kMaxTilt, kMaxTilt, 0},
        {"theta_z", "rad", "Rotation Rz, turns the axes by -theta_z", NdfParam::Kind::Azimuth,
         -kMaxTilt, kMaxTilt, 0}};
    return p;
  }
  std::shared_ptr<MicrofacetDistribution> make(const std::vector<double>& v) const override {
    return std::make_shared<EllipsoidDistribution>(EllipsoidParams{v[0], v[1], v[2], v[3], v[4]});
  }
  std::unique_ptr<NdfEvaluator> evaluator(const double* fit, bool reference) const override {
    auto plain = TemplateNdfModel<EllipsoidUnit>::evaluator(fit, true);
    if (reference) return plain;
    return std::make_unique<EllipsoidGradient>(fit, std::move(plain));
  }
  std::vector<double> initial(const NdfMoments& m) const override {
    // The peak R^T z along the mean normal.
    std::vector<double> v = NdfModel::initial(m);
    const Eigen::Vector3d w = rotation_z(v[4]) * m.mean_normal;
    v[2] = std::asin(std::clamp(w.y(), -1.0, 1.0));
    v[3] = std::atan2(-w.x(), w.z());
    return v;
  }
  void canonicalise(std::vector<double>& v) const override {
    // A spheroid (alpha_x == alpha_y) depends on its axis R^T z only: A^T A = a^2 I + (1 - a^2)
    // (R^T z)(R^T z)^T, so theta_z is free; report theta_z = 0 and the tilt of that axis.
    if (std::abs(v[0] - v[1]) <= 1e-6 * std::max(v[0], v[1])) {
      const Eigen::Vector3d axis =
          (rotation_x(v[2]) * rotation_y(v[3]) * rotation_z(v[4])).transpose() *
          Eigen::Vector3d(0, 0, 1);
      const Eigen::Vector3d w = axis.z() < 0 ? Eigen::Vector3d(-axis) : axis;
      v[2] = std::asin(std::clamp(w.y(), -1.0, 1.0));
      v[3] = std::atan2(-w.x(), w.z());
      v[4] = 0;
      return;
    }
    // theta_z into (-pi/2, pi/2]; (tx, ty, tz) == (-tx, -ty, tz + pi).
    const double k = std::ceil((v[4] - kPi / 2) / kPi);
    v[4] -= k * kPi;
    if (v[4] <= -kPi / 2) v[4] += kPi;
    if (static_cast<long long>(std::llround(k)) % 2 != 0) {
      v[2] = -v[2];
      v[3] = -v[3];
    }
  }
  NdfExportLobe export_lobe(const std::vector<double>&) const override {
    NdfExportLobe e;
    e.exact = false;
    e.note = "the ellipsoid's skew (its tilted peak) has no equivalent in Mitsuba 3 or pbrt-v4";
    return e;
  }
};

}  // namespace

std::unique_ptr<NdfModel> make_ellipsoid_model() { return std::make_unique<EllipsoidModel>(); }

}  // namespace microbrdf
