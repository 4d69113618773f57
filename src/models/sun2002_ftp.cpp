// Sun 2002 free travel probability (eq. 3.4.23), Smith's masking for the same surface, and the
// Beckmann distribution of its micro-normals.
#include <cmath>
#include <limits>
#include <string>

#include "microbrdf/error.hpp"
#include "microbrdf/sun2002.hpp"

namespace microbrdf::sun2002 {
namespace {

void check_s(double s) {
  if (!(s > 0) || !std::isfinite(s))
    throw InputError("Sun 2002: smoothness s = tau/sigma must be a positive number, got " +
                     std::to_string(s));
}

// tan(theta) for theta clamped to [0, pi/2]; +inf at pi/2.
double tan_clamped(double theta) {
  if (!(theta > 0)) return 0;  // also NaN -> 0 is not wanted: callers check NaN first
  if (theta >= M_PI / 2) return std::numeric_limits<double>::infinity();
  return std::tan(theta);
}

}  // namespace

double ftp(double theta, double s, double k_tau) {
  check_s(s);
  if (std::isnan(theta)) throw InputError("Sun 2002 FTP: theta is NaN");
  const double t = tan_clamped(theta);
  if (t == 0) return 1;
  if (std::isinf(t)) return 0;
  // exp(-s^2 / (4 t^2)) underflows to 0 for small t, giving exactly 1, the right limit.
  const double e = k_tau * t / (std::sqrt(2 * M_PI) * s) * std::exp(-s * s / (4 * t * t));
  return std::exp(-e);
}

double smith_lambda(double theta, double s) {
  check_s(s);
  if (std::isnan(theta)) throw InputError("Smith Lambda: theta is NaN");
  const double t = tan_clamped(theta);
  if (t == 0) return 0;
  if (std::isinf(t)) return std::numeric_limits<double>::infinity();
  const double a = s / (2 * t);
  if (a > 26) return 0;  // exp(-a^2) underflows; Lambda ~ exp(-a^2) / (4 a^3 sqrt(pi))
  return 0.5 * (std::exp(-a * a) / (a * std::sqrt(M_PI)) - std::erfc(a));
}

double smith_g1(double theta, double s) { return 1 / (1 + smith_lambda(theta, s)); }

double smith_at_mean_plane(double theta, double s) { return std::exp2(-smith_lambda(theta, s)); }

double beckmann_ndf(double c, double s) {
  check_s(s);
  if (!(c > 0)) return 0;
  c = std::min(c, 1.0);
  const double c2 = c * c, tan2 = (1 - c2) / c2;
  return s * s * std::exp(-s * s * tan2 / 4) / (4 * M_PI * c2 * c2);
}

}  // namespace microbrdf::sun2002
