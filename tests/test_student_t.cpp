// The Student-t NDF (normalisation, Smith Lambda, visible-normal sampling, limits) and the
// two-lobe mixture. References are computed here independently: the paper's slope density
// written out in the test, integrated in slope space by double-exponential quadrature.
#include <ceres/jet.h>

#include <algorithm>
#include <cstdio>
#include <limits>

#include "microbrdf/brdf_albedo.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/mixture_ndf.hpp"
#include "microbrdf/student_t.hpp"
#include "microbrdf/tabulated_distribution.hpp"
#include "models/student_t_math.hpp"
#include "test_microfacet_common.hpp"

using namespace microbrdf;
using mtest::Chart;
using mtest::direction;
using mtest::kPi;

namespace {

// ---- double-exponential quadrature (Takahasi-Mori), step h in the transformed variable ------
constexpr double kH = 1.0 / 14, kTauMax = 5.5;  // |x| up to e^192: heavy tails integrate fully

/// integral over the real line of f, x = c + s sinh(pi/2 sinh tau).
template <class F>
double sinh_sinh(const F& f, double c, double s) {
  double sum = 0;
  for (double tau = -kTauMax; tau <= kTauMax; tau += kH) {
    const double u = 0.5 * kPi * std::sinh(tau);
    sum += f(c + s * std::sinh(u)) * s * std::cosh(u) * 0.5 * kPi * std::cosh(tau);
  }
  return sum * kH;
}

/// integral over [0, inf) of f, x = s exp(pi/2 sinh tau).
template <class F>
double exp_sinh(const F& f, double s) {
  double sum = 0;
  for (double tau = -kTauMax; tau <= kTauMax; tau += kH) {
    const double x = s * std::exp(0.5 * kPi * std::sinh(tau));
    sum += f(x) * x * 0.5 * kPi * std::cosh(tau);
  }
  return sum * kH;
}

/// integral over [a, b] of f, x = (a + b)/2 + (b - a)/2 tanh(pi/2 sinh tau).
template <class F>
double tanh_sinh(const F& f, double a, double b) {
  double sum = 0;
  for (double tau = -3.5; tau <= 3.5; tau += kH) {
    const double u = 0.5 * kPi * std::sinh(tau), ch = std::cosh(u);
    const double w = 0.5 * kPi * std::cosh(tau) / (ch * ch);
    // distance to the nearer end computed without cancellation
    const double d = (b - a) / (std::exp(2 * u) + 1);  // (b - a)(1 - tanh u)/2
    const double x = u > 0 ? b - d : a + (b - a) / (std::exp(-2 * u) + 1);
    if (x > a && x < b) sum += f(x) * w;
  }
  return sum * kH * 0.5 * (b - a);
}

/// tanh_sinh over pieces of [a, b] at most `piece` long (its nodes are sparse mid-interval).
template <class F>
double tanh_sinh_pieces(const F& f, double a, double b, double piece) {
  const int n = std::max(1, int(std::ceil((b - a) / piece)));
  double sum = 0;
  for (int i = 0; i < n; ++i) sum += tanh_sinh(f, a + (b - a) * i / n, a + (b - a) * (i + 1) / n);
  return sum;
}

// ---- the paper's slope density, written out independently of the code -----------------------
struct Lobe {
  double ax, ay, phi, gamma;
};

/// P22 of Ribardiere et al. 2017 in the global frame: (g-1)^g / (pi ax ay) (g-1 + q)^-g with q the
/// slopes turned by -phi and scaled by the alphas; the power taken as (1 + q/(g-1))^-g =
/// exp(-g log1p(q/(g-1))), which does not lose g ulps for large g.
double paper_p22(const Lobe& l, double sx, double sy) {
  const double c = std::cos(l.phi), s = std::sin(l.phi);
  const double x = c * sx + s * sy, y = -s * sx + c * sy;
  const double q = x * x / (l.ax * l.ax) + y * y / (l.ay * l.ay), g = l.gamma;
  return std::exp(-g * std::log1p(q / (g - 1))) / (kPi * l.ax * l.ay);
}

/// integral of f(sx, sy) over the slope half-plane p <= p_max, with p the slope along azimuth
/// phi_v and t across it (p_max = inf: the whole plane). The inner integral over t is centred on
/// the ridge of the lobe's quadratic form q = A p^2 + 2B p t + C t^2 and scaled by its width at p.
template <class F>
double slope_integral(const F& f, const Lobe& l, double phi_v, double p_max) {
  const double ex = std::cos(phi_v), ey = std::sin(phi_v);
  auto q = [&](double p, double t) {
    const double sx = p * ex - t * ey, sy = p * ey + t * ex;
    const double c = std::cos(l.phi), s = std::sin(l.phi);
    const double x = c * sx + s * sy, y = -s * sx + c * sy;
    return x * x / (l.ax * l.ax) + y * y / (l.ay * l.ay);
  };
  const double A = q(1, 0), C = q(0, 1), B = 0.5 * (q(1, 1) - A - C), A1 = A - B * B / C;
  const double a = std::min(l.gamma - 1, 1e6);  // conditional width grows like sqrt(1 + A1 p^2/a)
  auto inner = [&](double p) {
    const double w = std::sqrt((1 + A1 * p * p / a) / C);
    return sinh_sinh([&](double t) { return f(p * ex - t * ey, p * ey + t * ex, p); }, -B * p / C,
                     w);
  };
  const double sp = 1 / std::sqrt(A1);  // width of the marginal along p
  const double below = exp_sinh([&](double x) { return inner(-x); }, sp);
  if (!(p_max < std::numeric_limits<double>::infinity()))
    return below + exp_sinh([&](double x) { return inner(x); }, sp);
  return below + tanh_sinh(inner, 0, p_max);
}

/// sigma+(v) = integral D(m) <v.m>+ dw = integral P22(s) <v.(-sx, -sy, 1)>+ ds over slopes.
template <class P>
double sigma_plus_reference(const P& p22, const Lobe& l, const Vec3& v) {
  const double r = std::hypot(v.x(), v.y());
  if (r == 0)
    return v.z() * slope_integral([&](double x, double y, double) { return p22(x, y); }, l, 0,
                                  std::numeric_limits<double>::infinity());
  return slope_integral([&](double x, double y, double p) { return p22(x, y) * (v.z() - r * p); },
                        l, std::atan2(v.y(), v.x()), v.z() / r);
}

/// The normal of slopes (sx, sy) and D(m) mz^4 dw -> ds, so D(m) mz^4 is a density in slopes.
double d_in_slopes(const MicrofacetDistribution& d, double sx, double sy) {
  const double n2 = 1 + sx * sx + sy * sy, iz = 1 / std::sqrt(n2);
  return d.D(Vec3(-sx * iz, -sy * iz, iz)) / (n2 * n2);
}

std::vector<Lobe> lobes() {
  std::vector<Lobe> v;
  for (double g : {1.5, 2.0, 5.0, 20.0}) {
    v.push_back({0.01, 0.01, 0, g});
    v.push_back({0.5, 0.5, 0, g});
    v.push_back({0.05, 0.3, 0.7, g});
    v.push_back({0.4, 0.012, -2.1, g});
  }
  return v;
}

/// n normals drawn by d.sample_visible(v, ...) from the generator seeded with `seed`.
std::vector<Vec3> draws(const MicrofacetDistribution& d, const Vec3& v, std::size_t n,
                        std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3> s(n);
  for (auto& m : s) m = d.sample_visible(v, u(rng), u(rng));
  return s;
}

StudentTDistribution make(const Lobe& l) {
  return StudentTDistribution(l.ax, l.ay, l.phi, l.gamma);
}

/// Chi-square of visible normals drawn for v, binned in the stretched slope plane aligned with
/// the view (x along the stretched view's azimuth, y across), where D_v is
/// <mu - x>+ P(x, y) / sigma, P = (1 + (x^2 + y^2)/a)^-(a+1)/pi, a = gamma - 1, mu = cot theta of
/// the stretched view. On the sphere D_v ~ mz^(2 gamma - 4) at the horizon, singular for
/// gamma < 2, which a quadrature on the sphere cannot follow; here each bin's expected count is
/// integrated by tanh-sinh quadrature (the open end mapped to a finite interval). Bins: x edges mu
/// - sqrt(a) tan(pi/2 (1 - k/nx)), y edges sqrt(a) tan(pi (j/ny - 1/2)).
mtest::ChiSquare slope_chi_square(const Lobe& l, const Vec3& v, const std::vector<Vec3>& samples,
                                  double alpha) {
  const double a = l.gamma - 1, ra = std::sqrt(a), c = std::cos(l.phi), s = std::sin(l.phi);
  const double vx = l.ax * (c * v.x() + s * v.y()), vy = l.ay * (-s * v.x() + c * v.y());
  const double r = std::hypot(vx, vy), ex = vx / r, ey = vy / r, mu = v.z() / r;
  const int nx = 24, ny = 16;
  std::vector<double> xe(nx + 1), ye(ny + 1);
  for (int k = 0; k <= nx; ++k) xe[k] = mu - ra * std::tan(0.5 * kPi * (1 - double(k) / nx));
  for (int j = 0; j <= ny; ++j) ye[j] = ra * std::tan(kPi * (double(j) / ny - 0.5));
  xe[0] = -std::numeric_limits<double>::infinity();
  ye[0] = -std::numeric_limits<double>::infinity();
  ye[ny] = std::numeric_limits<double>::infinity();
  std::vector<double> observed(nx * ny, 0), expected(nx * ny, 0);
  for (const Vec3& m : samples) {
    const double sx = -m.x() / m.z(), sy = -m.y() / m.z();
    const double X = (c * sx + s * sy) / l.ax, Y = (-s * sx + c * sy) / l.ay;
    const double x = ex * X + ey * Y, y = -ey * X + ex * Y;
    const int k = int(std::upper_bound(xe.begin(), xe.end(), x) - xe.begin()) - 1;
    const int j = int(std::upper_bound(ye.begin(), ye.end(), y) - ye.begin()) - 1;
    observed[std::clamp(k, 0, nx - 1) * ny + std::clamp(j, 0, ny - 1)] += 1;
  }
  // integral over [y0, y1] of P(x, y) dy: y = sqrt(q) tan t, q = a + x^2, leaves
  // (a/q)^(a+1) sqrt(q) cos^(2a) t / pi over t (q in logs: x reaches 1e300 in the open end).
  auto across = [&](double x, double y0, double y1) {
    const double ax = std::abs(x);
    const double lq = ax > 1 ? 2 * std::log(ax) + std::log1p(a / (ax * ax)) : std::log(a + x * x);
    const double rq = std::exp(0.5 * lq);
    const double f = std::exp((a + 1) * (std::log(a) - lq) + 0.5 * lq) / kPi;
    return f * tanh_sinh([&](double t) { return std::pow(std::cos(t), 2 * a); }, std::atan(y0 / rq),
                         std::atan(y1 / rq));
  };
  double total = 0;
  for (int k = 0; k < nx; ++k)
    for (int j = 0; j < ny; ++j) {
      auto f = [&](double x) { return (mu - x) * across(x, ye[j], ye[j + 1]); };
      // The open end decays like |x|^(-1 - eps), eps = 2 gamma - 3 (0.02 at gamma = 1.51):
      // x = x1 - sqrt(a) (t^(-1/eps) - 1) makes it ~constant in t on (0, 1] (nodes where x
      // overflows, t < ~1e-6 eps, are dropped with their ~1e-6 share).
      auto open_end = [&](double t) {
        const double e = 2 * l.gamma - 3, g = ra / e * std::pow(t, -1 / e - 1);
        const double v = f(xe[1] - ra * (std::pow(t, -1 / e) - 1)) * g;
        return std::isfinite(v) ? v : 0.0;
      };
      const double e = k == 0 ? tanh_sinh(open_end, 0, 1) : tanh_sinh(f, xe[k], xe[k + 1]);
      expected[k * ny + j] = e;
      total += e;
    }
  for (double& e : expected) e *= double(samples.size()) / total;
  return mtest::pooled_chi_square(observed, expected, alpha);
}

}  // namespace

TEST(student_t, ReferenceQuadratureIsExactOnGgx) {
  // The reference machinery against GGX's closed forms: sigma+ = vz (1 + Lambda_GGX).
  const Lobe l{0.2, 0.05, 0.4, 2};
  GgxDistribution g(l.ax, l.ay, l.phi);
  for (double th : {0.0, 30.0, 70.0, 89.0}) {
    Vec3 v = direction(th, 25);
    double ref = sigma_plus_reference([&](double x, double y) { return paper_p22(l, x, y); }, l, v);
    EXPECT_NEAR(ref / g.projected_area(v), 1.0, 1e-10) << th;
  }
}

TEST(student_t, NdfIntegratesToOne) {
  // integral D(m)(m.n) dw = integral D(m(s)) mz^4 ds over the slope plane, D from the code.
  double worst = 0;
  for (const Lobe& l : lobes()) {
    auto d = make(l);
    const double i =
        slope_integral([&](double x, double y, double) { return d_in_slopes(d, x, y); }, l, 0.3,
                       std::numeric_limits<double>::infinity());
    EXPECT_NEAR(i, 1.0, 1e-6) << d.describe();
    worst = std::max(worst, std::abs(i - 1));
  }
  std::printf("max |integral D(m)(m.n) dw - 1| over %zu Student-t lobes: %.2e\n", lobes().size(),
              worst);
}

TEST(student_t, NdfIntegratesToOneOnTheSphere) {
  // Independent of slope space: the sphere chart of the other microfacet tests. Half-integer
  // gamma keeps D (m.n) ~ (mz^2 + c)^-gamma mz^(2 gamma - 3) smooth at the horizon.
  for (const Lobe& l :
       {Lobe{0.3, 0.1, 0.5, 1.5}, Lobe{0.02, 0.05, -0.3, 3.5}, Lobe{0.2, 0.2, 0, 20}}) {
    auto d = make(l);
    Chart chart(mtest::lobe_stretch(l.ax, l.ay, l.phi));
    EXPECT_NEAR(chart.integrate([&](const Vec3& m) { return d.D(m) * m.z(); }, 512, 256), 1.0, 1e-6)
        << d.describe();
  }
}

TEST(student_t, DensityMatchesThePaperFormula) {
  // D(m) = P22(-mx/mz, -my/mz)/mz^4, the template with doubles, and the paper's form.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  for (const Lobe& l : lobes()) {
    auto d = make(l);
    for (int k = 0; k < 50; ++k) {
      Vec3 m = direction(89.9 * u(rng), 360 * u(rng));
      const double ref = paper_p22(l, -m.x() / m.z(), -m.y() / m.z()) / std::pow(m.z(), 4);
      EXPECT_NEAR(d.D(m), ref, 1e-12 * ref) << d.describe();
      EXPECT_NEAR(student_t_d(l.ax, l.ay, l.phi, l.gamma, m.x(), m.y(), m.z()), ref, 1e-12 * ref);
    }
  }
  // Near the horizon (z < 1e-60, where the code takes logs): D(m)(m.n)^4 = P22 of the slopes.
  auto d = make({0.1, 0.2, 0.3, 1.2});
  const double sx = 3e70, sy = -1e70, n = std::hypot(sx, sy);
  Vec3 m(-sx / n, -sy / n, 1 / n);
  const double p22 = paper_p22({0.1, 0.2, 0.3, 1.2}, sx, sy);
  EXPECT_NEAR(std::log(d.D(m)) + 4 * std::log(m.z()), std::log(p22), 1e-9);
}

TEST(student_t, TemplateDifferentiatesWithCeresJets) {
  // The fit evaluates the same template with ceres::Jet: its derivatives in (ax, ay, phi, gamma)
  // against central differences of the double version.
  using J = ceres::Jet<double, 4>;
  const double p[4] = {0.07, 0.2, 0.4, 3.5};
  for (double th : {5.0, 20.0, 50.0})
    for (double ph : {10.0, 100.0}) {
      const Vec3 m = direction(th, ph);
      J q[4];
      for (int i = 0; i < 4; ++i) q[i] = J(p[i], i);
      const J d = student_t_d(q[0], q[1], q[2], q[3], J(m.x()), J(m.y()), J(m.z()));
      EXPECT_NEAR(d.a, student_t_d(p[0], p[1], p[2], p[3], m.x(), m.y(), m.z()), 1e-12 * d.a);
      for (int i = 0; i < 4; ++i) {
        double hi[4] = {p[0], p[1], p[2], p[3]}, lo[4] = {p[0], p[1], p[2], p[3]};
        const double h = 1e-6 * std::max(1.0, p[i]);
        hi[i] += h;
        lo[i] -= h;
        const double fd = (student_t_d(hi[0], hi[1], hi[2], hi[3], m.x(), m.y(), m.z()) -
                           student_t_d(lo[0], lo[1], lo[2], lo[3], m.x(), m.y(), m.z())) /
                          (2 * h);
        EXPECT_NEAR(d.v[i], fd, 1e-6 * (std::abs(fd) + d.a)) << "parameter " << i << " at " << th;
      }
    }
}

TEST(student_t, LambdaMatchesTheSmithIntegral) {
  // G1(v) = vz / sigma+(v), sigma+ integrated from the paper's P22.
  double worst = 0;
  int n = 0;
  double worst_sigma = 0;
  for (double g : {1.6, 2.0, 3.0, 5.0, 20.0, 1e4})
    for (const Lobe& l : {Lobe{0.3, 0.3, 0, g}, Lobe{0.02, 0.4, 0.6, g}}) {
      auto d = make(l);
      for (double th : {0.0, 15.0, 45.0, 70.0, 80.0, 85.0, 89.0})
        for (double ph : {0.0, 50.0, 135.0}) {
          Vec3 v = direction(th, ph);
          const double sigma =
              sigma_plus_reference([&](double x, double y) { return paper_p22(l, x, y); }, l, v);
          const double e = std::abs(d.G1(v) - std::min(1.0, v.z() / sigma));
          EXPECT_LT(e, 1e-9) << d.describe() << " view " << th << "," << ph;
          EXPECT_NEAR(d.projected_area(v) / sigma, 1.0, 1e-8) << d.describe() << " view " << th;
          worst = std::max(worst, e);
          worst_sigma = std::max(worst_sigma, std::abs(d.projected_area(v) / sigma - 1));
          ++n;
        }
    }
  std::printf("max |G1 - vz/sigma+| over %d Student-t (lobe, view) pairs: %.2e; sigma+: %.2e\n", n,
              worst, worst_sigma);
}

TEST(student_t, SlopeInversionsSolveTheirCdfs) {
  // The 1-D inversions behind sample_visible, in the stretched configuration (alpha = 1): the
  // visible slope x solves C(x) = u C(mu), C(x) = integral_-inf^x (mu - t) P2(t) dt, and the
  // family's quantile w solves F(w) = u. References by quadrature of the paper's P22 (P2 its
  // integral over y) and of (1 + w^2)^-(b + 1/2), normalised numerically. Error measure: the
  // residual divided by the density, i.e. the error in the slope to first order, per (1 + |x|).
  double worst_x = 0, worst_w = 0;
  for (double g : {1.6, 2.0, 3.0, 8.0, 1e4}) {
    const Lobe unit{1, 1, 0, g};
    const double a = g - 1;
    auto p2 = [&](double t) {
      return sinh_sinh([&](double y) { return paper_p22(unit, t, y); }, 0,
                       std::sqrt((a + t * t) / a));
    };
    auto below = [&](double mu, double x) {  // integral_-inf^x (mu - t) P2(t) dt
      auto f = [&](double t) { return (mu - t) * p2(t); };
      const double lo = std::min(x, 0.0);
      // exp-sinh spaces its nodes evenly in ln d only near its scale: put it at |lo|
      const double tail = exp_sinh([&](double d) { return f(lo - d); }, std::max(1.0, -lo));
      return x > 0 ? tail + tanh_sinh_pieces(f, 0, x, 2) : tail;
    };
    const microbrdf::student_t::Slopes slopes(g);
    for (double mu : {0.05, 0.5, 2.0, 30.0}) {
      const double total = below(mu, mu);
      for (double u : {1e-9, 0.01, 0.3, 0.5, 0.8, 0.999, 1 - 1e-7}) {
        const double x = slopes.visible_slope(mu, u);
        // above the median, the part over [x, mu] (no cancellation against the total)
        const double r =
            u <= 0.5 ? below(mu, x) - u * total
                     : tanh_sinh_pieces([&](double t) { return (mu - t) * p2(t); }, x, mu, 2) -
                           (1 - u) * total;
        const double e = std::abs(r) / ((mu - x) * p2(x)) / (1 + std::abs(x));
        EXPECT_LT(e, 1e-10) << "gamma " << g << " mu " << mu << " u " << u << " x " << x;
        worst_x = std::max(worst_x, e);
      }
    }
    // The family f_b for the marginal (b = a) and for the slope across the view (b = a + 1/2).
    for (double b : {a, a + 0.5}) {
      const microbrdf::student_t::Shape shape(b);
      auto f = [&](double w) { return std::exp(-(b + 0.5) * std::log1p(w * w)); };
      const double sb = 1 / std::sqrt(b + 0.5);  // the width of f
      const double norm = sinh_sinh(f, 0, sb);
      for (double u : {1e-12, 1e-4, 0.1, 0.45, 0.7, 0.99999}) {
        const double w = shape.quantile(u);
        const double sw = std::max(sb, std::abs(w));
        const double lower = w <= 0 ? exp_sinh([&](double d) { return f(w - d); }, sw)
                                    : norm - exp_sinh([&](double d) { return f(w + d); }, sw);
        const double e = std::abs(lower / norm - u) / (f(w) / norm) / (1 + std::abs(w));
        EXPECT_LT(e, 1e-10) << "b " << b << " u " << u << " w " << w;
        worst_w = std::max(worst_w, e);
      }
    }
  }
  std::printf("slope inversions: visible slope %.2e (1 + |x|), quantile %.2e (1 + |w|)\n", worst_x,
              worst_w);
}

TEST(student_t, LambdaInfiniteForGammaAtMostOneAndAHalf) {
  // The mean |slope| diverges for gamma <= 1.5: every oblique view is fully shadowed.
  for (double g : {1.1, 1.5}) {
    StudentTDistribution d(0.2, 0.1, 0.3, g);
    EXPECT_EQ(d.G1(Vec3(0, 0, 1)), 1.0);
    EXPECT_EQ(d.lambda(Vec3(0, 0, 1)), 0.0);
    EXPECT_TRUE(std::isinf(d.lambda(direction(1, 40))));
    EXPECT_EQ(d.G1(direction(60, 40)), 0.0);
  }
  // Just above 1.5 the integral is finite but large (the reference confirms it).
  const Lobe l{0.2, 0.2, 0, 1.55};
  Vec3 v = direction(30, 0);
  double sigma = sigma_plus_reference([&](double x, double y) { return paper_p22(l, x, y); }, l, v);
  EXPECT_NEAR(make(l).projected_area(v) / sigma, 1.0, 1e-8);
}

TEST(student_t, GammaTwoIsGgx) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(0, 1);
  double worst = 0;
  for (int k = 0; k < 20; ++k) {
    const double ax = 0.005 * std::pow(200.0, u(rng)), ay = 0.005 * std::pow(200.0, u(rng));
    const double phi = 2 * kPi * u(rng);
    StudentTDistribution s(ax, ay, phi, 2.0);
    GgxDistribution g(ax, ay, phi);
    for (int j = 0; j < 50; ++j) {
      Vec3 m = direction(89.5 * u(rng), 360 * u(rng));
      EXPECT_NEAR(s.D(m), g.D(m), 1e-12 * g.D(m)) << s.describe();
      EXPECT_NEAR(s.lambda(m), g.lambda(m), 1e-12 * (1 + g.lambda(m))) << s.describe();
      worst = std::max(worst, std::abs(s.D(m) / g.D(m) - 1));
    }
  }
  std::printf("gamma = 2 vs GGX: max relative difference in D %.2e\n", worst);
}

TEST(student_t, LargeGammaApproachesBeckmann) {
  // (1 + q/(g-1))^-g = e^-q (1 + O(q^2/g)): within ~1e-3 at gamma = 1e4 where D >= 1% of its peak.
  for (const Lobe& l : {Lobe{0.3, 0.3, 0, 1e4}, Lobe{0.05, 0.2, 1.0, 1e4}}) {
    auto s = make(l);
    BeckmannDistribution b(l.ax, l.ay, l.phi);
    const double peak = b.D(Vec3(0, 0, 1));
    double worst = 0;
    std::mt19937_64 rng(4);
    std::uniform_real_distribution<double> u(0, 1);
    for (int k = 0; k < 2000; ++k) {
      Vec3 m = direction(60 * u(rng), 360 * u(rng));
      if (b.D(m) < 0.01 * peak) continue;
      worst = std::max(worst, std::abs(s.D(m) / b.D(m) - 1));
    }
    EXPECT_LT(worst, 1e-3) << s.describe();
    double worst_lambda = 0;
    EXPECT_GT(worst, 1e-6) << "not Beckmann itself";
    for (double th : {20.0, 60.0, 85.0}) {
      const double ls = s.lambda(direction(th, 30)), lb = b.lambda(direction(th, 30));
      EXPECT_NEAR(ls, lb, 2e-3) << th;
      worst_lambda = std::max(worst_lambda, std::abs(ls - lb) / (1 + lb));
    }
    std::printf("%s vs Beckmann: D within %.2e relative (D >= 1%% of the peak), Lambda %.2e\n",
                s.describe().c_str(), worst, worst_lambda);
  }
}

namespace {

/// Visible normals drawn for 4 views of each lobe, against pdf_visible: gamma >= 2 on the
/// sphere chart of the other microfacet tests, heavier tails in slope space (slope_chi_square)
/// where the sphere's quadrature fails near the horizon. `family`: Bonferroni over both tests.
void visible_normal_chi_square(const std::vector<Lobe>& cases, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const std::vector<std::pair<double, double>> views = {
      {0.0, 0.0}, {40.0, 20.0}, {75.0, 200.0}, {89.0, 100.0}};
  const int family = 24;
  for (const Lobe& l : cases) {
    auto d = make(l);
    Chart chart(mtest::lobe_stretch(l.ax, l.ay, l.phi));
    for (auto [th, ph] : views) {
      Vec3 v = direction(th, ph);
      std::vector<Vec3> s(80000);
      for (auto& m : s) {
        m = d.sample_visible(v, u(rng), u(rng));
        ASSERT_GT(m.z(), 0);
        ASSERT_NEAR(m.norm(), 1.0, 1e-12);
        ASSERT_GE(v.dot(m), -1e-12);
      }
      const bool heavy = l.gamma < 2 && th > 0;
      auto r =
          heavy ? slope_chi_square(l, v, s, 0.01 / family)
                : mtest::chi_square(
                      chart, s, [&](const Vec3& m) { return d.pdf_visible(v, m); }, 0.01 / family);
      if (!heavy) {
        EXPECT_NEAR(r.total_expected, 1.0, 2e-3) << d.describe();
      }
      EXPECT_LT(r.chi2, r.critical) << d.describe() << " view " << th << "; dof " << r.dof;
      std::printf("%-52s view %4.0f deg: chi2/dof %.3f\n", d.describe().c_str(), th,
                  r.chi2 / r.dof);
      for (int k = 0; k < 20; ++k)  // sampling_pdf is the visible-normal density
        EXPECT_EQ(d.sampling_pdf(v, s[k]), d.pdf_visible(v, s[k]));
    }
  }
}

}  // namespace

TEST(student_t, VisibleNormalSamplingChiSquare) {
  visible_normal_chi_square(
      {{0.1, 0.4, 0.6, 2.0}, {0.2, 0.05, -0.9, 3}, {0.01, 0.02, 0.3, 8}, {0.3, 0.1, 2.0, 1e4}},
      2024);
}

TEST(student_t, VisibleNormalSamplingChiSquareHeavyTails) {
  visible_normal_chi_square({{0.3, 0.3, 0, 1.6}, {0.05, 0.2, 1.2, 1.51}}, 2025);
}

TEST(student_t, SamplingTellsGammasApart) {
  // The chi-square above can fail: gamma 3 samples against the gamma 4 density.
  StudentTDistribution a(0.2, 0.2, 0, 3), b(0.2, 0.2, 0, 4);
  Vec3 v = direction(50, 0);
  auto r = mtest::chi_square(Chart(mtest::lobe_stretch(0.2, 0.2, 0)), draws(a, v, 100000, 6),
                             [&](const Vec3& m) { return b.pdf_visible(v, m); });
  EXPECT_GT(r.chi2, r.critical);
}

TEST(student_t, HeavyTailSamplingBelowOneAndAHalf) {
  // gamma 1.1 and 1.3: at the normal the draws are the visible normals (= D(m)(m.n)); off it no
  // visible-normal density exists and D(m)(m.n) is drawn, which sampling_pdf reports. D(m)(m.n)
  // diverges at the horizon here, so the draws are checked in slope space: with the slopes
  // turned by -phi and divided by the alphas, (X, Y) has the isotropic density
  // (1 + R^2/a)^-(a+1)/pi, a = gamma - 1, so 1 - (1 + R^2/a)^-a and atan2(Y, X) are uniform.
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> u(0, 1);
  const double ax = 0.2, ay = 0.1, phi = 0.4;
  for (double g : {1.1, 1.3}) {
    StudentTDistribution d(ax, ay, phi, g);
    for (double th : {0.0, 60.0}) {
      Vec3 v = direction(th, 10);
      const int nb = 20, n = 100000;
      std::vector<double> observed(nb * nb, 0), expected(nb * nb, double(n) / (nb * nb));
      for (int k = 0; k < n; ++k) {
        Vec3 m = d.sample_visible(v, u(rng), u(rng));
        ASSERT_GT(m.z(), 0);
        ASSERT_NEAR(m.norm(), 1.0, 1e-12);
        const double sx = -m.x() / m.z(), sy = -m.y() / m.z();
        const double x = (std::cos(phi) * sx + std::sin(phi) * sy) / ax;
        const double y = (-std::sin(phi) * sx + std::cos(phi) * sy) / ay;
        const double a = g - 1, c = -std::expm1(-a * std::log1p((x * x + y * y) / a));
        const double t = std::atan2(y, x) / (2 * kPi) + 0.5;
        observed[std::min(nb - 1, int(c * nb)) * nb + std::min(nb - 1, int(t * nb))] += 1;
        if (k < 10) {
          EXPECT_NEAR(d.sampling_pdf(v, m), d.pdf(m), 1e-12 * d.pdf(m));
        }
      }
      auto r = mtest::pooled_chi_square(observed, expected, 0.01 / 4);
      EXPECT_LT(r.chi2, r.critical) << d.describe() << " view " << th;
    }
  }
}

TEST(student_t, WeakWhiteFurnace) {
  // integral G1(v) D(m) <v.m>+ dw / (v.n) = 1 (Heitz 2014), on the sphere chart. (Heavier tails,
  // gamma < 2, make D <v.m>+ singular at the horizon for the chart; LambdaMatchesTheSmithIntegral
  // checks the same identity for them in slope space.)
  for (const Lobe& l : {Lobe{0.3, 0.3, 0, 2.5}, Lobe{0.3, 0.1, 0.7, 3}, Lobe{0.02, 0.02, 0, 10}}) {
    auto d = make(l);
    Chart chart(mtest::lobe_stretch(l.ax, l.ay, l.phi));
    for (double th : {0.0, 45.0, 75.0, 89.0}) {
      Vec3 v = direction(th, 30);
      double i = chart.integrate(
          [&](const Vec3& m) { return d.G1(v, m) * d.D(m) * std::max(0.0, v.dot(m)); }, 384, 384);
      EXPECT_NEAR(i / v.z(), 1.0, 1e-3) << d.describe() << " theta_v " << th;
    }
  }
}

TEST(student_t, BrdfAlbedoAtMostOneAndReciprocal) {
  // The Smith single-scattering BRDF with F = 1 reflects at most what it receives, and is
  // reciprocal, for Student-t lobes from heavy to nearly Beckmann.
  auto mirror = std::make_shared<PerfectMirrorFresnel>();
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(0, 1);
  double worst = 0;
  for (const Lobe& l : {Lobe{0.3, 0.3, 0, 1.6}, Lobe{0.2, 0.05, 0.5, 2.5}, Lobe{0.5, 0.4, 1, 50}}) {
    MicrofacetBrdf b(std::make_shared<StudentTDistribution>(l.ax, l.ay, l.phi, l.gamma), mirror);
    for (double th : {0.0, 30.0, 60.0, 80.0, 89.0}) {
      const double a = directional_albedo_sampled(b, direction(th, 40), 550e-9, 128);
      EXPECT_LE(a, 1.0 + 1e-9) << b.describe() << " theta_i " << th;
      EXPECT_GT(a, 0.3) << b.describe() << " theta_i " << th;
      worst = std::max(worst, a);
    }
    for (int k = 0; k < 300; ++k) {
      Vec3 wi = direction(89 * u(rng), 360 * u(rng)), wo = direction(89 * u(rng), 360 * u(rng));
      const double f1 = b.eval(wi, wo, 550e-9), f2 = b.eval(wo, wi, 550e-9);
      EXPECT_NEAR(f1, f2, 1e-12 * std::max(1.0, f1)) << b.describe();
      EXPECT_GE(f1, 0);
    }
  }
  std::printf("largest Student-t directional albedo (F = 1): %.9f\n", worst);
}

TEST(student_t, SpecialFunctionsAtExtremes) {
  // Slopes reach 1e150 for gamma near 1 (normals within 1e-150 of the horizon): finite, unit,
  // above the horizon; u = 0 and u -> 1 stay finite; gamma 1e6 still samples.
  for (double g : {1.01, 1.1, 1.6, 2.0, 1e6}) {
    StudentTDistribution d(0.05, 0.3, 0.2, g);
    for (double th : {0.0, 30.0, 89.9})
      for (double u1 : {0.0, 1e-300, 1e-12, 0.5, 1 - 1e-12, std::nextafter(1.0, 0.0)})
        for (double u2 : {0.0, 0.5, std::nextafter(1.0, 0.0)}) {
          Vec3 m = d.sample_visible(direction(th, 70), u1, u2);
          ASSERT_TRUE(std::isfinite(m.x()) && std::isfinite(m.y()) && m.z() > 0)
              << d.describe() << " " << th << " " << u1 << " " << u2;
          ASSERT_NEAR(m.norm(), 1.0, 1e-12);
          ASSERT_TRUE(std::isfinite(d.D(m))) << d.describe();
        }
  }
}

TEST(student_t, BadParameters) {
  EXPECT_THROW(StudentTDistribution(0.1, 0.1, 0, 1.0), InputError);
  EXPECT_THROW(StudentTDistribution(0.1, 0.1, 0, 2e6), InputError);
  EXPECT_THROW(StudentTDistribution(0.1, 0.1, 0, std::nan("")), InputError);
  EXPECT_THROW(StudentTDistribution(0.0, 0.1, 0, 2), InputError);
  EXPECT_THROW(StudentTDistribution(0.1, 11, 0, 2), InputError);
  EXPECT_THROW(StudentTDistribution(0.1, 0.1, INFINITY, 2), InputError);
  StudentTDistribution d(0.1, 0.2, kPi / 6, 3.5);
  EXPECT_EQ(d.describe(), "student-t alpha=(0.1, 0.2) phi=30 deg gamma=3.5");
  EXPECT_EQ(d.params().gamma, 3.5);
}

// ---- the two-lobe mixture ------------------------------------------------------------------

namespace {
std::shared_ptr<MixtureDistribution> ggx_beckmann(double w) {
  return std::make_shared<MixtureDistribution>(
      std::make_shared<GgxDistribution>(0.05, 0.1, 0.3),
      std::make_shared<BeckmannDistribution>(0.4, 0.3, 1.0), w);
}
}  // namespace

TEST(mixture_ndf, NormalisedAndLinear) {
  auto d = ggx_beckmann(0.3);
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(0, 1);
  for (int k = 0; k < 100; ++k) {
    Vec3 m = direction(89 * u(rng), 360 * u(rng));
    EXPECT_NEAR(d->D(m), 0.3 * d->first().D(m) + 0.7 * d->second().D(m), 1e-12 * d->D(m));
  }
  // Both lobes resolved: a chart for each, the integral of the mixture over each chart.
  for (const auto& stretch :
       {mtest::lobe_stretch(0.05, 0.1, 0.3), mtest::lobe_stretch(0.4, 0.3, 1)})
    EXPECT_NEAR(Chart(stretch).integrate([&](const Vec3& m) { return d->D(m) * m.z(); }, 512, 512),
                1.0, 1e-6);
}

TEST(mixture_ndf, LambdaIsTheIntegralOfItsD) {
  // sigma+ integrated from the mixture's own D: in slope space, with the quadrature laid out
  // for the narrow lobe (its nodes resolve the wide one too), and on the sphere chart.
  auto d = ggx_beckmann(0.4);
  const Lobe narrow{0.05, 0.1, 0.3, 2};
  auto mix = [&](double x, double y) { return d_in_slopes(*d, x, y); };
  Chart chart(mtest::lobe_stretch(0.2, 0.2, 0));
  for (double th : {0.0, 20.0, 60.0, 80.0, 88.0})
    for (double ph : {0.0, 120.0}) {
      Vec3 v = direction(th, ph);
      EXPECT_NEAR(d->projected_area(v) / sigma_plus_reference(mix, narrow, v), 1.0, 1e-8)
          << th << "," << ph;
      // the kink at v.m = 0 limits the chart to ~1e-5
      const double s2 = chart.integrate(
          [&](const Vec3& m) { return d->D(m) * std::max(0.0, v.dot(m)); }, 512, 512);
      EXPECT_NEAR(d->projected_area(v) / s2, 1.0, 1e-4) << th << "," << ph;
    }
}

TEST(mixture_ndf, SamplingChiSquare) {
  for (double w : {0.3, 0.8}) {
    auto d = ggx_beckmann(w);
    Chart chart(mtest::lobe_stretch(0.15, 0.15, 0));
    for (double th : {0.0, 50.0, 85.0}) {
      Vec3 v = direction(th, 60);
      const std::vector<Vec3> s = draws(*d, v, 200000, 99 + int(th) + int(100 * w));
      auto r = mtest::chi_square(
          chart, s, [&](const Vec3& m) { return d->pdf_visible(v, m); }, 0.01 / 6, 32, 64);
      EXPECT_NEAR(r.total_expected, 1.0, 2e-3);
      EXPECT_LT(r.chi2, r.critical) << d->describe() << " view " << th << "; dof " << r.dof;
      for (int k = 0; k < 20; ++k)
        EXPECT_NEAR(d->sampling_pdf(v, s[k]), d->pdf_visible(v, s[k]),
                    1e-12 * d->pdf_visible(v, s[k]));
    }
  }
}

TEST(mixture_ndf, SamplingPdfIsTheMixtureOfTheLobesSamplers) {
  // A tabulated lobe draws an approximation of its visible normals with a known density:
  // sampling_pdf must follow the draws (P1 q1 + (1 - P1) q2), not pdf_visible.
  TabulatedDistributionOptions o;
  o.sigma_bins = 128;
  auto table = std::make_shared<TabulatedDistribution>(
      tabulate(BeckmannDistribution(0.3, 0.2, 0.5), "beckmann", 257), o);
  MixtureDistribution d(std::make_shared<GgxDistribution>(0.1), table, 0.5);
  for (double th : {30.0, 70.0}) {
    Vec3 v = direction(th, 20);
    const double p1 = d.first_lobe_probability(v);
    EXPECT_NEAR(p1, 0.5 * d.first().projected_area(v) / d.projected_area(v), 1e-12);
    const std::vector<Vec3> s = draws(d, v, 200000, 5 + int(th));
    auto r = mtest::chi_square(
        Chart(mtest::lobe_stretch(0.2, 0.2, 0)), s,
        [&](const Vec3& m) { return d.sampling_pdf(v, m); }, 0.01 / 2);
    EXPECT_LT(r.chi2, r.critical) << "view " << th;
    // ... and differs from the visible-normal density somewhere.
    double differs = 0;
    for (int k = 0; k < 1000; ++k)
      differs = std::max(differs, std::abs(d.sampling_pdf(v, s[k]) / d.pdf_visible(v, s[k]) - 1));
    EXPECT_GT(differs, 1e-3);
  }
  // A lobe with infinite sigma+ (Student-t, gamma <= 1.5) off the normal takes every draw.
  MixtureDistribution h(std::make_shared<GgxDistribution>(0.1),
                        std::make_shared<StudentTDistribution>(0.2, 0.2, 0, 1.2), 0.5);
  EXPECT_EQ(h.first_lobe_probability(direction(40, 0)), 0.0);
  // Finite lobes at normal incidence: P1 = w exactly (sigma+(n) = 1 for both).
  EXPECT_NEAR(ggx_beckmann(0.25)->first_lobe_probability(Vec3(0, 0, 1)), 0.25, 1e-15);
}

TEST(mixture_ndf, EdgesAndErrors) {
  auto g = std::make_shared<GgxDistribution>(0.1);
  auto b = std::make_shared<BeckmannDistribution>(0.3);
  EXPECT_THROW(MixtureDistribution(g, nullptr, 0.5), InputError);
  EXPECT_THROW(MixtureDistribution(g, b, 1.5), InputError);
  EXPECT_THROW(MixtureDistribution(g, b, std::nan("")), InputError);
  // Weight 1 is the first lobe exactly (and a weightless infinite lobe adds nothing).
  MixtureDistribution one(g, std::make_shared<StudentTDistribution>(0.2, 0.2, 0, 1.2), 1.0);
  Vec3 v = direction(50, 10), m = direction(20, 30);
  EXPECT_EQ(one.lambda(v), g->lambda(v));
  EXPECT_EQ(one.D(m), g->D(m));
  EXPECT_EQ(one.sample_visible(v, 0.3, 0.6), g->sample_visible(v, 0.3, 0.6));
  EXPECT_EQ(MixtureDistribution(g, b, 0.5).describe(),
            "mixture w=0.5 of [" + g->describe() + "] + [" + b->describe() + "]");
}
