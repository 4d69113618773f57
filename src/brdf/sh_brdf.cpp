// ShBrdf: construction, evaluation, albedo, Gibbs damping and projection of other BRDFs
// (W92 sections 2.2-2.5, docs/theory.md §6.3, 6.5, 6.6). Sampling: sh_sampling.cpp; files:
// sh_io.cpp.
#include "microbrdf/sh_brdf.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "microbrdf/brdf.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/quadrature.hpp"
#include "microbrdf/sh_basis.hpp"
#include "sh_internal.hpp"

namespace microbrdf {
namespace {
constexpr double kPi = 3.14159265358979323846;
}

namespace detail {

void sh_rotate_z(const ShOddBasis& basis, Eigen::MatrixXd& a, double alpha) {
  // Y(Rz(alpha) w) = R Y(w) with 2x2 blocks on the pairs (l, m), (l, -m), m > 0:
  //   Y_{l,m}(Rw) = c Y_{l,m} - s Y_{l,-m},  Y_{l,-m}(Rw) = s Y_{l,m} + c Y_{l,-m},
  // c = cos(m alpha), s = sin(m alpha). Returns R^T A R in place (column, then row operations).
  for (int j = 0; j < basis.size(); ++j) {
    const int l = basis.l(j), m = basis.m(j);
    if (m <= 0) continue;
    const int jp = j, jm = sh_odd_index(l, -m);
    const double c = std::cos(m * alpha), s = std::sin(m * alpha);
    Eigen::VectorXd cp = a.col(jp), cm = a.col(jm);
    a.col(jp) = c * cp + s * cm;
    a.col(jm) = -s * cp + c * cm;
    Eigen::RowVectorXd rp = a.row(jp), rm = a.row(jm);
    a.row(jp) = c * rp + s * rm;
    a.row(jm) = -s * rp + c * rm;
  }
}

}  // namespace detail

ShBrdf::ShBrdf(int lmax, const Eigen::MatrixXd& m, nlohmann::json meta)
    : basis_(lmax), meta_(std::move(meta)), lazy_(std::make_shared<LazyTable>()) {
  const int n = basis_.size();
  if (m.rows() != n || m.cols() != n)
    throw InputError("ShBrdf: matrix is " + std::to_string(m.rows()) + " x " +
                     std::to_string(m.cols()) + ", lmax " + std::to_string(lmax) + " needs " +
                     std::to_string(n) + " x " + std::to_string(n));
  if (!m.allFinite()) throw InputError("ShBrdf: matrix has non-finite coefficients");
  m_ = 0.5 * (m + m.transpose());
  if (meta_.is_null()) meta_ = nlohmann::json::object();
  // Isotropy decides only how the sampler tabulates (sample/pdf stay consistent either way), so
  // a loose tolerance lets noisy estimates of isotropic surfaces use the small table.
  Eigen::MatrixXd r = m_;
  detail::sh_rotate_z(basis_, r, 1.0);  // 1 rad: m alpha is never a multiple of 2 pi
  const double norm = m_.norm();
  isotropic_ = norm == 0 || (r - m_).norm() <= 2e-2 * norm;
  // Exact block structure in |m| (isotropic_average(), Lambertian, ...): evaluate per block.
  bool blocky = true;
  for (int j = 0; j < n && blocky; ++j)
    for (int k = 0; k < n; ++k)
      if (std::abs(basis_.m(j)) != std::abs(basis_.m(k)) && m_(j, k) != 0) {
        blocky = false;
        break;
      }
  if (blocky) {
    blocks_.resize(lmax + 1);
    for (int j = 0; j < n; ++j) blocks_[std::abs(basis_.m(j))].idx.push_back(j);
    for (auto& b : blocks_) {
      const int k = static_cast<int>(b.idx.size());
      b.m.resize(k, k);
      for (int a = 0; a < k; ++a)
        for (int c = 0; c < k; ++c) b.m(a, c) = m_(b.idx[a], b.idx[c]);
    }
    std::erase_if(blocks_, [](const MBlock& b) { return b.idx.empty(); });
  }
}

ShBrdf ShBrdf::isotropic_average() const {
  // R(alpha)^T M R(alpha) holds cos/sin of (m +- m') alpha with |m +- m'| <= 2 lmax, so the
  // equally spaced (2 lmax + 1)-point rule averages it exactly.
  const int k = 2 * lmax() + 1, n = basis_.size();
  Eigen::MatrixXd avg = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < k; ++i) {
    Eigen::MatrixXd r = m_;
    detail::sh_rotate_z(basis_, r, 2 * kPi * i / k);
    avg += r;
  }
  avg /= k;
  for (int j = 0; j < n; ++j)  // remove the rounding residue of the cancelled couplings
    for (int c = 0; c < n; ++c)
      if (std::abs(basis_.m(j)) != std::abs(basis_.m(c))) avg(j, c) = 0;
  nlohmann::json meta = meta_;
  meta["isotropic_average"] = true;
  ShBrdf out(lmax(), avg, std::move(meta));
  out.horizon_cos_ = horizon_cos_;
  return out;
}

ShBrdf ShBrdf::from_estimator(const ShEstimator& e, nlohmann::json meta) {
  if (meta.is_null()) meta = nlohmann::json::object();
  if (!meta.contains("incident_count")) meta["incident_count"] = e.incident_count();
  if (!meta.contains("ray_count")) meta["ray_count"] = e.ray_count();
  if (!meta.contains("q")) meta["q"] = e.q();
  if (!meta.contains("mean_energy")) meta["mean_energy"] = e.mean_energy();
  return ShBrdf(e.basis().lmax(), e.raw(), std::move(meta));
}

ShBrdf ShBrdf::project(const Brdf& brdf, int lmax, double wavelength_m, int n_theta,
                       nlohmann::json meta) {
  const ShOddBasis basis(lmax);
  if (n_theta <= 0) n_theta = lmax + 8;
  const int n_phi = 2 * n_theta;
  std::vector<double> gx, gw;
  gauss_legendre(n_theta, gx, gw);
  const int nd = n_theta * n_phi, nb = basis.size();
  std::vector<Vec3> dir(nd);
  Eigen::VectorXd wcos(nd);  // quadrature weight x cos(theta)
  for (int t = 0; t < n_theta; ++t)
    for (int p = 0; p < n_phi; ++p) {
      const double z = 0.5 * (gx[t] + 1), s = std::sqrt(std::max(0.0, 1 - z * z));
      const double phi = (p + 0.5) * 2 * kPi / n_phi;
      dir[t * n_phi + p] = Vec3(s * std::cos(phi), s * std::sin(phi), z);
      wcos[t * n_phi + p] = 0.5 * gw[t] * (2 * kPi / n_phi) * z;
    }
  Eigen::MatrixXd y(nb, nd);
  for (int a = 0; a < nd; ++a) basis.eval(dir[a], y.col(a).data());
  Eigen::MatrixXd f(nd, nd);
#pragma omp parallel for schedule(dynamic, 16)
  for (int a = 0; a < nd; ++a)
    for (int b = 0; b < nd; ++b)
      f(a, b) = brdf.eval(dir[a], dir[b], wavelength_m) * wcos[a] * wcos[b];
  // The odd completion in both arguments doubles each hemisphere integral (docs/theory.md §6.4):
  // x 4.
  Eigen::MatrixXd m = 4.0 * (y * f * y.transpose());
  if (meta.is_null()) meta = nlohmann::json::object();
  meta["source"] = "projection of " + brdf.describe();
  meta["quadrature"] = {{"n_theta", n_theta}, {"n_phi", n_phi}};
  meta["wavelength_m"] = wavelength_m;
  return ShBrdf(lmax, m, std::move(meta));
}

double ShBrdf::cosine_weighted(const Vec3& wi, const Vec3& wo) const {
  const int n = basis_.size();
  Eigen::VectorXd yi(n), yo(n);
  basis_.eval(wi, yi.data());
  basis_.eval(wo, yo.data());
  if (!blocks_.empty()) {
    double f = 0;
    Eigen::VectorXd a, b;
    for (const auto& blk : blocks_) {
      const int k = static_cast<int>(blk.idx.size());
      a.resize(k);
      b.resize(k);
      for (int q = 0; q < k; ++q) {
        a[q] = yi[blk.idx[q]];
        b[q] = yo[blk.idx[q]];
      }
      f += a.dot(blk.m * b);
    }
    return f;
  }
  return yi.dot(m_.selfadjointView<Eigen::Upper>() * yo);
}

double ShBrdf::eval(const Vec3& wi, const Vec3& wo, double) const {
  if (!(wi.z() > 0) || !(wo.z() > 0)) return 0.0;
  const double f = cosine_weighted(wi, wo);
  if (!(f > 0)) return 0.0;
  const double ci = std::max(wi.z() / wi.norm(), horizon_cos_);
  const double co = std::max(wo.z() / wo.norm(), horizon_cos_);
  return f / (ci * co);
}

ShBrdf::Bound ShBrdf::bind(const Vec3& w) const {
  Eigen::VectorXd y(basis_.size());
  basis_.eval(w, y.data());
  return Bound{w, m_ * y};
}

double ShBrdf::eval_bound(const Bound& b, const Vec3& other) const {
  if (!(b.w.z() > 0) || !(other.z() > 0)) return 0.0;
  Eigen::VectorXd y(basis_.size());
  basis_.eval(other, y.data());
  const double f = y.dot(b.c);
  if (!(f > 0)) return 0.0;
  const double ci = std::max(b.w.z() / b.w.norm(), horizon_cos_);
  const double co = std::max(other.z() / other.norm(), horizon_cos_);
  return f / (ci * co);
}

double ShBrdf::albedo(const Vec3& wi) const {
  if (!(wi.z() > 0)) return 0.0;
  const int n = basis_.size();
  Eigen::VectorXd yi(n);
  basis_.eval(wi, yi.data());
  const Eigen::Map<const Eigen::VectorXd> h(basis_.hemisphere_integrals().data(), n);
  return yi.dot(m_ * h) / std::max(wi.z() / wi.norm(), horizon_cos_);
}

ShBrdf ShBrdf::damped(int l_filter, double width) const {
  if (l_filter < 0) throw InputError("Gibbs damping: l_filter must be >= 0");
  if (!(width > 0)) throw InputError("Gibbs damping: width must be > 0");
  const int n = basis_.size();
  Eigen::VectorXd w(n);
  for (int j = 0; j < n; ++j) {
    const double d = basis_.l(j) - l_filter;
    w[j] = d <= 0 ? 1.0 : std::exp(-d * d / (2 * width * width));
  }
  nlohmann::json meta = meta_;
  meta["damping"] = {{"l_filter", l_filter}, {"width", width}};
  ShBrdf out(lmax(), w.asDiagonal() * m_ * w.asDiagonal(), std::move(meta));
  out.horizon_cos_ = horizon_cos_;
  return out;
}

std::string ShBrdf::describe() const {
  return "spherical-harmonic BRDF (Westin 1992), lmax " + std::to_string(lmax()) + ", " +
         std::to_string(basis_.size()) + " kept functions, " +
         (isotropic_ ? "isotropic" : "anisotropic");
}

}  // namespace microbrdf
