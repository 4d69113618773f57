// Sun 2002 analytic BRDF (eq. 3.5.3), as printed and in the standard microfacet form.
#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>

#include "microbrdf/error.hpp"
#include "microbrdf/sun2002.hpp"

namespace microbrdf::sun2002 {
namespace {

// Gamma_0 from the cosine of the polar angle (avoids acos in the hot path).
double ftp_cos(double c, double s) {
  if (c >= 1) return 1;
  if (!(c > 0)) return 0;
  const double t = std::sqrt(std::max(0.0, 1 - c * c)) / c;
  if (t == 0) return 1;
  return std::exp(-t / (std::sqrt(2 * M_PI) * s) * std::exp(-s * s / (4 * t * t)));
}

// Nodes and weights of 16-point Gauss-Legendre on [-1, 1] (Newton on P_16).
const std::array<std::pair<double, double>, 16>& gauss_legendre16() {
  static const auto table = [] {
    std::array<std::pair<double, double>, 16> t{};
    const int n = 16;
    for (int i = 0; i < n; ++i) {
      double x = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 0;
      for (int it = 0; it < 100; ++it) {
        double p0 = 1, p1 = x;
        for (int k = 2; k <= n; ++k) {
          const double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
          p0 = p1;
          p1 = p2;
        }
        dp = n * (x * p1 - p0) / (x * x - 1);
        const double dx = p1 / dp;
        x -= dx;
        if (std::abs(dx) < 1e-16) break;
      }
      t[i] = {x, 2 / ((1 - x * x) * dp * dp)};
    }
    return t;
  }();
  return table;
}

}  // namespace

FtpTerms parse_ftp_terms(const std::string& name) {
  if (name == "both") return FtpTerms::Both;
  if (name == "view") return FtpTerms::ViewOnly;
  if (name == "light") return FtpTerms::LightOnly;
  if (name == "none") return FtpTerms::None;
  throw InputError("free travel probabilities '" + name + "': give both, view, light or none");
}

std::string ftp_terms_name(FtpTerms t) {
  switch (t) {
    case FtpTerms::Both:
      return "both";
    case FtpTerms::ViewOnly:
      return "view";
    case FtpTerms::LightOnly:
      return "light";
    case FtpTerms::None:
      return "none";
  }
  return "both";
}

BrdfForm parse_brdf_form(const std::string& name) {
  if (name == "standard") return BrdfForm::Standard;
  if (name == "published") return BrdfForm::AsPublished;
  throw InputError("Sun 2002 BRDF form '" + name + "': give standard or published");
}

std::string brdf_form_name(BrdfForm f) {
  return f == BrdfForm::AsPublished ? "published" : "standard";
}

double brdf(const Eigen::Vector3d& wi_in, const Eigen::Vector3d& wo_in, double s, BrdfForm form,
            const Fresnel* fresnel, double wavelength_m, FtpTerms ftp) {
  if (!(s > 0) || !std::isfinite(s))
    throw InputError("Sun 2002 BRDF: smoothness s must be positive, got " + std::to_string(s));
  const double ni = wi_in.norm(), no = wo_in.norm();
  if (!(ni > 0) || !(no > 0)) return 0;
  const Eigen::Vector3d wi = wi_in / ni, wo = wo_in / no;
  const double ci = wi.z(), co = wo.z();
  if (!(ci > 0) || !(co > 0)) return 0;
  const Eigen::Vector3d h = (wi + wo).normalized();
  const double ch = h.z();      // cos(theta), theta = polar angle of the micro-normal
  const double cd = wi.dot(h);  // cos(delta/2), delta = angle between wi and wo
  const double R = fresnel ? fresnel->eval(cd, wavelength_m) : 1.0;
  const bool light = ftp == FtpTerms::Both || ftp == FtpTerms::LightOnly;
  const bool view = ftp == FtpTerms::Both || ftp == FtpTerms::ViewOnly;
  const double G = (light ? ftp_cos(ci, s) : 1.0) * (view ? ftp_cos(co, s) : 1.0);
  if (form == BrdfForm::AsPublished) {
    // Eq. 3.5.3 exactly as printed.
    const double tan2 = (1 - ch * ch) / (ch * ch);
    return R * s * s * std::exp(-s * s * tan2 / 4) / (16 * M_PI * ch * ch * ch * cd) * G;
  }
  return R * beckmann_ndf(ch, s) * G / (4 * ci * co);
}

double published_over_standard(const Eigen::Vector3d& wi_in, const Eigen::Vector3d& wo_in) {
  const Eigen::Vector3d wi = wi_in.normalized(), wo = wo_in.normalized();
  if (!(wi.z() > 0) || !(wo.z() > 0)) return 0;
  const Eigen::Vector3d h = (wi + wo).normalized();
  return h.z() * wi.z() * wo.z() / wi.dot(h);
}

double albedo(double theta_i, double s, BrdfForm form, const Fresnel* fresnel, double wavelength_m,
              bool weight_cos, int n_u, int n_phi) {
  if (!(theta_i >= 0 && theta_i < M_PI / 2))
    throw InputError("Sun 2002 albedo: theta_i must be in [0, 90) deg");
  if (n_u < 1 || n_phi < 1) throw InputError("Sun 2002 albedo: quadrature sizes must be >= 1");
  const Eigen::Vector3d wi(std::sin(theta_i), 0, std::cos(theta_i));
  // Half-vector space: h at polar angle th_h, azimuth phi; tan(th_h) = 2u/s, so the slope
  // density is exp(-u^2). wo is above the horizon iff tan(th_h) < tan(th_i) cos(phi) +
  // sqrt(1 + tan^2(th_i) cos^2(phi)) (solve (2 (wi.h) h - wi).z = 0); the u range of each phi
  // stops there (or at u = 7), so the integrand is smooth on it (Gamma_0 takes it to 0 at the
  // horizon with all derivatives): composite 16-point Gauss-Legendre in u, midpoint rule in the
  // periodic phi (spectrally accurate).
  const auto& gl = gauss_legendre16();
  const int panels = (n_u + 15) / 16;
  const double dphi = 2 * M_PI / n_phi, ti = std::tan(theta_i);
  double sum = 0;
  for (int b = 0; b < n_phi; ++b) {
    const double ph = (b + 0.5) * dphi, cph = std::cos(ph), sph = std::sin(ph);
    const double tcut = ti * cph + std::sqrt(1 + ti * ti * cph * cph);
    const double U = std::min(7.0, 0.5 * s * tcut), pw = U / panels;
    for (int pnl = 0; pnl < panels; ++pnl)
      for (const auto& [x, w] : gl) {
        const double u = (pnl + 0.5 * (x + 1)) * pw;
        const double t = 2 * u / s, th = std::atan(t);
        const double dth = (2 / s) / (1 + t * t) * 0.5 * pw * w;
        const double sh = std::sin(th), chh = std::cos(th);
        const Eigen::Vector3d h(sh * cph, sh * sph, chh);
        const double d = wi.dot(h);
        if (!(d > 0)) continue;
        const Eigen::Vector3d wo = 2 * d * h - wi;
        if (!(wo.z() > 0)) continue;
        const double f = brdf(wi, wo, s, form, fresnel, wavelength_m);
        sum += f * (weight_cos ? wo.z() : 1.0) * 4 * d * sh * dth * dphi;
      }
  }
  return sum;
}

}  // namespace microbrdf::sun2002
