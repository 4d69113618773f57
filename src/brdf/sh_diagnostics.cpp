// Diagnostics of SH BRDFs (include/microbrdf/sh_brdf.hpp): albedos and ringing.
#include <cmath>
#include <vector>

#include "microbrdf/sh_brdf.hpp"

namespace microbrdf {
namespace {
constexpr double kPi = 3.14159265358979323846;
}

std::vector<ShAlbedoPoint> sh_albedo_table(const ShBrdf& b) {
  std::vector<ShAlbedoPoint> t;
  for (double deg : {0.0, 30.0, 45.0, 60.0, 75.0, 85.0}) {
    const double r = deg * kPi / 180;
    t.push_back({deg, b.albedo(Vec3(std::sin(r), 0, std::cos(r)))});
  }
  return t;
}

double sh_hemispherical_albedo(const ShBrdf& b) {
  const auto& basis = b.basis();
  const Eigen::Map<const Eigen::VectorXd> h(basis.hemisphere_integrals().data(), basis.size());
  return h.dot(b.matrix() * h) / kPi;
}

ShRinging sh_ringing(const ShBrdf& b) {
  const auto& basis = b.basis();
  const int n = basis.size();
  std::vector<Vec3> wi, wo;
  for (int t = 0; t < 9; ++t)
    for (int p = 0; p < 8; ++p) {
      const double th = (t + 0.5) * kPi / 18, ph = p * kPi / 4;
      wi.emplace_back(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
    }
  for (int t = 0; t < 18; ++t)
    for (int p = 0; p < 36; ++p) {
      const double th = (t + 0.5) * kPi / 36, ph = (p + 0.5) * kPi / 18;
      wo.emplace_back(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
    }
  // All pairs as one matrix product.
  Eigen::MatrixXd yi(n, static_cast<Eigen::Index>(wi.size())),
      yo(n, static_cast<Eigen::Index>(wo.size()));
  for (std::size_t k = 0; k < wi.size(); ++k) basis.eval(wi[k], yi.col(Eigen::Index(k)).data());
  for (std::size_t k = 0; k < wo.size(); ++k) basis.eval(wo[k], yo.col(Eigen::Index(k)).data());
  const Eigen::MatrixXd f = yi.transpose() * b.matrix() * yo;
  ShRinging r;
  r.negative_fraction =
      static_cast<double>((f.array() < 0).count()) / static_cast<double>(f.size());
  r.min_cosine_weighted = f.minCoeff();
  r.max_cosine_weighted = f.maxCoeff();
  return r;
}

}  // namespace microbrdf
