#include "microbrdf/level.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>

#include "microbrdf/error.hpp"
#include "microbrdf/units.hpp"

namespace microbrdf {

std::string LevelingSpec::name() const {
  switch (mode) {
    case Leveling::None:
      return "none";
    case Leveling::Plane:
      return "plane";
    case Leveling::Polynomial:
      return "poly" + std::to_string(degree);
  }
  return "?";
}

LevelingSpec LevelingSpec::parse(const std::string& text) {
  if (text == "none") return {Leveling::None, 0};
  if (text == "plane") return {Leveling::Plane, 1};
  if (text == "poly") return {Leveling::Polynomial, 2};
  if (text.rfind("poly", 0) == 0 && text.size() == 5 && text[4] >= '1' && text[4] <= '6') {
    int d = text[4] - '0';
    return d == 1 ? LevelingSpec{Leveling::Plane, 1} : LevelingSpec{Leveling::Polynomial, d};
  }
  throw InputError("unknown levelling '" + text + "' (use none, plane, poly2 ... poly6)");
}

namespace {

double rms_about_mean(const Surface& s) {
  double sum = 0, sum2 = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (!s.valid[i]) continue;
    sum += s.z[i];
    ++n;
  }
  if (n == 0) return 0;
  double mean = sum / static_cast<double>(n);
  for (std::size_t i = 0; i < s.size(); ++i)
    if (s.valid[i]) sum2 += (s.z[i] - mean) * (s.z[i] - mean);
  return std::sqrt(sum2 / static_cast<double>(n));
}

// Monomials u^i v^j with i + j <= degree, graded order: 1, u, v, u^2, uv, v^2, ...
void monomials(double u, double v, int degree, Eigen::VectorXd& out) {
  int k = 0;
  for (int d = 0; d <= degree; ++d)
    for (int j = 0; j <= d; ++j) out[k++] = std::pow(u, d - j) * std::pow(v, j);
}

}  // namespace

LevelingResult level_surface(Surface& s, const LevelingSpec& spec) {
  LevelingResult r;
  r.rms_before = rms_about_mean(s);
  if (spec.mode == Leveling::None) {
    s.meta.leveling = "none";
    r.description = "none";
    r.rms_after = r.rms_before;
    return r;
  }
  const int degree = spec.mode == Leveling::Plane ? 1 : spec.degree;
  const int nterms = (degree + 1) * (degree + 2) / 2;
  if (s.valid_count() < static_cast<std::size_t>(3 * nterms))
    throw InputError("too few valid samples (" + std::to_string(s.valid_count()) + " of " +
                     std::to_string(s.nx) + " x " + std::to_string(s.ny) + ") to fit a degree-" +
                     std::to_string(degree) + " polynomial (at least " +
                     std::to_string(3 * nterms) + "; --level none skips levelling)");

  // Coordinates scaled to [-1, 1] for conditioning; heights about a reference for precision.
  const double hx = std::max<double>(1.0, (static_cast<double>(s.nx) - 1) / 2.0);
  const double hy = std::max<double>(1.0, (static_cast<double>(s.ny) - 1) / 2.0);
  const double cx = (static_cast<double>(s.nx) - 1) / 2.0,
               cy = (static_cast<double>(s.ny) - 1) / 2.0;
  double zref = 0;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (s.valid[i]) {
      zref = s.z[i];
      break;
    }

  Eigen::MatrixXd ata = Eigen::MatrixXd::Zero(nterms, nterms);
  Eigen::VectorXd atb = Eigen::VectorXd::Zero(nterms);
  Eigen::VectorXd m(nterms);
  for (std::size_t iy = 0; iy < s.ny; ++iy) {
    double v = (static_cast<double>(iy) - cy) / hy;
    for (std::size_t ix = 0; ix < s.nx; ++ix) {
      std::size_t i = iy * s.nx + ix;
      if (!s.valid[i]) continue;
      monomials((static_cast<double>(ix) - cx) / hx, v, degree, m);
      ata.selfadjointView<Eigen::Lower>().rankUpdate(m);
      atb += m * (s.z[i] - zref);
    }
  }
  ata = ata.selfadjointView<Eigen::Lower>();
  Eigen::VectorXd c = ata.colPivHouseholderQr().solve(atb);
  c[0] += zref;

  for (std::size_t iy = 0; iy < s.ny; ++iy) {
    double v = (static_cast<double>(iy) - cy) / hy;
    for (std::size_t ix = 0; ix < s.nx; ++ix) {
      std::size_t i = iy * s.nx + ix;
      if (!s.valid[i]) continue;
      monomials((static_cast<double>(ix) - cx) / hx, v, degree, m);
      s.z[i] -= m.dot(c);
    }
  }
  s.z0 += c[0];
  s.meta.leveling = spec.name();
  r.coefficients.assign(c.data(), c.data() + nterms);
  r.rms_after = rms_about_mean(s);
  // Tilt of the fitted plane (first-order terms), in degrees.
  double gx = c[1] / (hx * s.dx), gy = c[2] / (hy * s.dy);
  char buf[200];
  std::snprintf(buf, sizeof buf, "%s (tilt %.4g deg, rms %s before, %s after)", spec.name().c_str(),
                std::atan(std::hypot(gx, gy)) * 180.0 / M_PI, format_length(r.rms_before).c_str(),
                format_length(r.rms_after).c_str());
  r.description = buf;
  return r;
}

}  // namespace microbrdf
