#include "microbrdf/level.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

#include "core/helper_pool.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/threads.hpp"
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

// Rows of the scan handed to one helper-pool item; each row's sums land in its own slot, so the
// reduction below runs in row order whatever the thread count (results do not depend on it).
constexpr std::size_t kRowsPerItem = 16;

// Sums over the valid samples of each row, on the helper threads: f(z) per sample, one slot per
// row (reduced in row order by the caller).
template <class F>
std::vector<double> row_sums(const Surface& s, std::vector<std::size_t>* counts, F f) {
  std::vector<double> sums(s.ny, 0.0);
  if (counts) counts->assign(s.ny, 0);
  const std::size_t items = (s.ny + kRowsPerItem - 1) / kRowsPerItem;
  const std::function<void(std::size_t)> item = [&](std::size_t it) {
    const std::size_t y1 = std::min(s.ny, (it + 1) * kRowsPerItem);
    for (std::size_t iy = it * kRowsPerItem; iy < y1; ++iy) {
      const double* z = s.z.data() + iy * s.nx;
      const std::uint8_t* ok = s.valid.data() + iy * s.nx;
      double sum = 0;
      std::size_t n = 0;
      for (std::size_t ix = 0; ix < s.nx; ++ix)
        if (ok[ix]) {
          sum += f(z[ix]);
          ++n;
        }
      sums[iy] = sum;
      if (counts) (*counts)[iy] = n;
    }
  };
  detail::HelperPool::instance().run(items, resolve_thread_count(0), item);
  return sums;
}

// RMS about the mean of the valid heights: two passes (mean, then squares about it), each over
// rows on the helper threads (the rms is reported before and after levelling).
double rms_about_mean(const Surface& s) {
  std::vector<std::size_t> counts;
  const std::vector<double> sums = row_sums(s, &counts, [](double z) { return z; });
  double sum = 0;
  std::size_t n = 0;
  for (std::size_t iy = 0; iy < s.ny; ++iy) {
    sum += sums[iy];
    n += counts[iy];
  }
  if (n == 0) return 0;
  const double mean = sum / static_cast<double>(n);
  const std::vector<double> sq =
      row_sums(s, nullptr, [mean](double z) { return (z - mean) * (z - mean); });
  double sum2 = 0;
  for (double v : sq) sum2 += v;
  return std::sqrt(sum2 / static_cast<double>(n));
}

// Index of the monomial u^a v^b in the graded order 1, u, v, u^2, uv, v^2, ... (degree a + b).
int monomial_index(int a, int b) {
  const int d = a + b;
  return d * (d + 1) / 2 + b;
}

// The normal equations of the least-squares polynomial, built separably: for monomials
// u^a v^b, (A^T A)_{(a,b),(c,d)} = sum over rows of v^(b+d) * sum over the row of u^(a+c), and
// (A^T z)_{(a,b)} = sum over rows of v^b * sum over the row of u^a z. One pass over the samples
// with 2 degree + 1 products each, instead of a rank-1 update of the matrix per sample.
void normal_equations(const Surface& s, int degree, double zref, double cx, double hx, double cy,
                      double hy, Eigen::MatrixXd& ata, Eigen::VectorXd& atb) {
  const int pu = 2 * degree + 1;  // powers of u needed for A^T A
  const int pz = degree + 1;      // powers of u needed for A^T z
  const int per_row = pu + pz;
  std::vector<double> rows(s.ny * static_cast<std::size_t>(per_row), 0.0);
  const std::size_t items = (s.ny + kRowsPerItem - 1) / kRowsPerItem;
  const std::function<void(std::size_t)> item = [&](std::size_t it) {
    std::vector<double> pw(static_cast<std::size_t>(pu));
    const std::size_t y1 = std::min(s.ny, (it + 1) * kRowsPerItem);
    for (std::size_t iy = it * kRowsPerItem; iy < y1; ++iy) {
      double* su = rows.data() + iy * static_cast<std::size_t>(per_row);
      double* sz = su + pu;
      for (std::size_t ix = 0; ix < s.nx; ++ix) {
        const std::size_t i = iy * s.nx + ix;
        if (!s.valid[i]) continue;
        const double u = (static_cast<double>(ix) - cx) / hx, dz = s.z[i] - zref;
        double p = 1;
        for (int k = 0; k < pu; ++k, p *= u) {
          su[k] += p;
          if (k < pz) sz[k] += p * dz;
        }
      }
    }
  };
  detail::HelperPool::instance().run(items, resolve_thread_count(0), item);

  // Moments over the rows, in row order: mu[p][q] = sum v^q su[p], mz[p][q] = sum v^q sz[p].
  const int pv = 2 * degree + 1;
  std::vector<double> mu(static_cast<std::size_t>(pu * pv), 0.0),
      mz(static_cast<std::size_t>(pz * pv), 0.0);
  for (std::size_t iy = 0; iy < s.ny; ++iy) {
    const double v = (static_cast<double>(iy) - cy) / hy;
    const double* su = rows.data() + iy * static_cast<std::size_t>(per_row);
    const double* sz = su + pu;
    double vq = 1;
    for (int q = 0; q < pv; ++q, vq *= v) {
      for (int p = 0; p + q < pu; ++p) mu[static_cast<std::size_t>(p * pv + q)] += vq * su[p];
      for (int p = 0; p < pz && p + q < pz; ++p)
        mz[static_cast<std::size_t>(p * pv + q)] += vq * sz[p];
    }
  }
  const int nterms = (degree + 1) * (degree + 2) / 2;
  ata.setZero(nterms, nterms);
  atb.setZero(nterms);
  for (int d1 = 0; d1 <= degree; ++d1)
    for (int b1 = 0; b1 <= d1; ++b1) {
      const int a1 = d1 - b1, k1 = monomial_index(a1, b1);
      atb[k1] = mz[static_cast<std::size_t>(a1 * pv + b1)];
      for (int d2 = 0; d2 <= degree; ++d2)
        for (int b2 = 0; b2 <= d2; ++b2) {
          const int a2 = d2 - b2;
          ata(k1, monomial_index(a2, b2)) = mu[static_cast<std::size_t>((a1 + a2) * pv + b1 + b2)];
        }
    }
}

// Subtracts the polynomial with coefficients c (graded order) from the valid samples: per row,
// the coefficients of u (sums over v^b) once, then Horner's rule per sample.
void subtract_polynomial(Surface& s, int degree, const Eigen::VectorXd& c, double cx, double hx,
                         double cy, double hy) {
  const std::size_t items = (s.ny + kRowsPerItem - 1) / kRowsPerItem;
  const std::function<void(std::size_t)> item = [&](std::size_t it) {
    std::vector<double> r(static_cast<std::size_t>(degree + 1));
    const std::size_t y1 = std::min(s.ny, (it + 1) * kRowsPerItem);
    for (std::size_t iy = it * kRowsPerItem; iy < y1; ++iy) {
      const double v = (static_cast<double>(iy) - cy) / hy;
      for (int a = 0; a <= degree; ++a) {
        double sum = 0, vb = 1;
        for (int b = 0; a + b <= degree; ++b, vb *= v) sum += c[monomial_index(a, b)] * vb;
        r[static_cast<std::size_t>(a)] = sum;
      }
      for (std::size_t ix = 0; ix < s.nx; ++ix) {
        const std::size_t i = iy * s.nx + ix;
        if (!s.valid[i]) continue;
        const double u = (static_cast<double>(ix) - cx) / hx;
        double p = r[static_cast<std::size_t>(degree)];
        for (int a = degree - 1; a >= 0; --a) p = p * u + r[static_cast<std::size_t>(a)];
        s.z[i] -= p;
      }
    }
  };
  detail::HelperPool::instance().run(items, resolve_thread_count(0), item);
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

  Eigen::MatrixXd ata;
  Eigen::VectorXd atb;
  normal_equations(s, degree, zref, cx, hx, cy, hy, ata, atb);
  Eigen::VectorXd c = ata.colPivHouseholderQr().solve(atb);
  c[0] += zref;
  subtract_polynomial(s, degree, c, cx, hx, cy, hy);
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
