#pragma once
// atan2 to within 3e-13 rad, about three times cheaper than the C library's: for hot loops that
// only look a direction up in a table of angles (the sigma+ grid of tabulated NDFs), where
// glibc's correctly rounded atan2 was the largest single cost.
//
// Method: |y|, |x| ordered so that r = min/max is in [0, 1]; above tan(pi/8) the identity
// atan r = pi/4 + atan((r - 1)/(r + 1)) brings the argument to |t| <= tan(pi/8); there
// atan t = t P(t^2) with P of degree 7, a least-squares fit at Chebyshev nodes of t^2 on
// [0, tan^2(pi/8)] (largest error 2.8e-13 over that interval); then the octant and the signs.
// atan2(+-0, +-0) gives 0 (the C library gives +-0 or +-pi by the signs of the zeros); otherwise
// the sign of y decides the sign of the result as in the C library (atan2(-0, -1) = -pi).
#include <cmath>

namespace microbrdf::detail {

inline double fast_atan2(double y, double x) {
  constexpr double kPi = 3.14159265358979323846;
  constexpr double kTanPi8 = 0.41421356237309504880;
  const double ax = std::abs(x), ay = std::abs(y);
  const double hi = ax > ay ? ax : ay, lo = ax > ay ? ay : ax;
  if (!(hi > 0)) return hi == 0 ? 0.0 : std::atan2(y, x);  // zeros, or a NaN
  if (std::isinf(hi)) return std::atan2(y, x);
  double r = lo / hi, base = 0;
  if (r > kTanPi8) {
    r = (r - 1) / (r + 1);
    base = 0.25 * kPi;
  }
  const double u = r * r;
  const double p =
      0.9999999999992712 +
      u * (-0.33333333278382116 +
           u * (0.19999993188603726 +
                u * (-0.14285391248571544 +
                     u * (0.11103534724081054 +
                          u * (-0.08993215551495012 +
                               u * (0.06976997559472924 + u * -0.037701604531671866))))));
  double a = base + r * p;
  if (ay > ax) a = 0.5 * kPi - a;
  if (x < 0) a = kPi - a;
  return std::signbit(y) ? -a : a;
}

}  // namespace microbrdf::detail
