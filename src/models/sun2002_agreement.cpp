// How Sun's section 4 experiment agrees with the analytic curves (include/microbrdf/sun2002.hpp):
// the largest deviations and the best-fitting k_tau.
#include <algorithm>
#include <cmath>
#include <limits>

#include "microbrdf/sun2002.hpp"

namespace microbrdf::sun2002 {

double fit_k_tau(double s, const std::vector<double>& theta, const std::vector<double>& g) {
  if (theta.empty()) return std::numeric_limits<double>::quiet_NaN();
  auto cost = [&](double lk) {
    double c = 0;
    for (std::size_t i = 0; i < theta.size(); ++i) {
      const double d = ftp(theta[i], s, std::exp(lk)) - g[i];
      c += d * d;
    }
    return c;
  };
  double lo = std::log(0.01), hi = std::log(100.0);
  const double r = (std::sqrt(5.0) - 1) / 2;
  double x1 = hi - r * (hi - lo), x2 = lo + r * (hi - lo), f1 = cost(x1), f2 = cost(x2);
  for (int it = 0; it < 100; ++it) {
    if (f1 < f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - r * (hi - lo);
      f1 = cost(x1);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + r * (hi - lo);
      f2 = cost(x2);
    }
  }
  return std::exp(0.5 * (lo + hi));
}

void FtpDeviation::take(double d, double t) {
  if (std::abs(d) > std::abs(diff)) {
    diff = d;
    theta = t;
  }
}

FtpAgreement compare_ftp(const FtpSimResult& r) {
  FtpAgreement a;
  const double s = r.params.s;
  std::vector<double> th, g_leave, g_any;
  for (const auto& pt : r.points) {
    a.rays += pt.rays;
    a.max_standard_error_leaving = std::max(a.max_standard_error_leaving, pt.se_leaving);
    const double t = pt.theta;
    if (!(t < M_PI / 2 - 1e-12)) continue;  // pi/2 is not simulated (exactly 0)
    const double g = ftp(t, s);
    a.leaving_minus_sun.take(pt.gamma_leaving - g, t);
    a.leaving_minus_smith_g1.take(pt.gamma_leaving - smith_g1(t, s), t);
    a.leaving_minus_smith_mean_plane.take(pt.gamma_leaving - smith_at_mean_plane(t, s), t);
    a.any_minus_sun.take(pt.gamma_any - g, t);
    th.push_back(t);
    g_leave.push_back(pt.gamma_leaving);
    g_any.push_back(pt.gamma_any);
  }
  a.best_k_tau_leaving = fit_k_tau(s, th, g_leave);
  a.best_k_tau_any = fit_k_tau(s, th, g_any);
  return a;
}

}  // namespace microbrdf::sun2002
