// Beckmann per-sample work, before/after in one run: the visible-normal sampler, Smith's Lambda
// and the slope quantiles of the library (src/models/beckmann_math.*) against the previous
// implementation kept here as the yardstick (libm erfc/exp/log; Winitzki's erfinv start and
// safeguarded Newton). GGX and the ellipsoid (whose previous sampler, building its frame per
// call, is a second yardstick) are timed alongside.
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "microbrdf/microfacet.hpp"
#include "models/beckmann_math.hpp"

using namespace microbrdf;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kSqrtPi = 1.77245385090551602730;
constexpr std::size_t kBatch = 4096;

// ---- the previous implementation (yardstick) -------------------------------------------------
double legacy_erfinv_guess(double t) {
  t = std::clamp(t, -1 + 1e-16, 1 - 1e-16);
  const double a = 0.147;
  const double l = std::log(1 - t * t);
  const double b = 2 / (kPi * a) + 0.5 * l;
  return std::copysign(std::sqrt(std::sqrt(b * b - l / a) - b), t);
}

double legacy_slope(double mu, double u) {
  if (!(mu < 1e8)) {
    double x = legacy_erfinv_guess(2 * u - 1);
    for (int it = 0; it < 50; ++it) {
      const double f = u < 0.5 ? 0.5 * std::erfc(-x) - u : (1 - u) - 0.5 * std::erfc(x);
      const double dx = f * kSqrtPi * std::exp(x * x);
      x -= dx;
      if (!(std::abs(dx) > 1e-8 * (1 + std::abs(x)))) break;
    }
    return x;
  }
  const double e_mu = std::exp(-mu * mu);
  const double c_mu = mu * 0.5 * kSqrtPi * std::erfc(-mu) + 0.5 * e_mu;
  const bool upper = u > 0.5;
  const double tail = (1 - u) * c_mu;
  double x = mu > 1 ? legacy_erfinv_guess(2 * u - 1) - 0.5 / mu
                    : mu - std::sqrt(-std::log(std::max(u, 1e-300)));
  if (upper && mu < 5) {
    const double z0 = std::sqrt(2 * tail / e_mu);
    if (!(x < mu) || x < mu - z0) x = mu - z0;
  }
  double lo = -30, hi = mu;
  if (!(x > lo && x < hi)) x = 0.5 * (std::max(lo, -6.0) + hi);
  const double target = std::log(upper ? tail : u * c_mu);
  for (int it = 0; it < 200; ++it) {
    const double c = mu * 0.5 * kSqrtPi * std::erfc(-x) + 0.5 * std::exp(-x * x);
    const double p = (mu - x) * std::exp(-x * x);
    double g, dg;
    if (!upper) {
      g = std::log(c) - target;
      dg = p / c;
    } else {
      const double s = c_mu - c;
      g = s > 0 ? std::log(s) - target : -1e300;
      dg = s > 0 ? -p / s : -1e300;
    }
    if (upper ? g < 0 : g > 0)
      hi = x;
    else
      lo = x;
    const double xn = x - g / dg;
    if (std::abs(xn - x) <= 1e-8 * (1 + std::abs(x))) return std::clamp(xn, lo, hi);
    if (xn > lo && xn < hi) {
      x = xn;
    } else {
      x = 0.5 * (lo + hi);
      if (hi - lo <= 1e-14 * (1 + std::abs(x))) return x;
    }
  }
  return x;
}

class LegacyBeckmann final : public MicrofacetDistribution {
 public:
  LegacyBeckmann(double ax, double ay, double phi)
      : ax_(ax), ay_(ay), c_(std::cos(phi)), s_(std::sin(phi)) {}
  double D(const Vec3& m) const override {
    const double z = m.z();
    if (z <= 0) return 0;
    const double x = c_ * m.x() + s_ * m.y(), y = -s_ * m.x() + c_ * m.y();
    const double z2 = z * z;
    const double e = (x * x / (ax_ * ax_) + y * y / (ay_ * ay_)) / z2;
    return std::exp(-e) / (kPi * ax_ * ay_ * z2 * z2);
  }
  double lambda(const Vec3& v) const override {
    const double x = c_ * v.x() + s_ * v.y(), y = -s_ * v.x() + c_ * v.y(), z = v.z();
    const double t2 = ax_ * ax_ * x * x + ay_ * ay_ * y * y;
    if (t2 <= 0) return 0;
    const double a = z / std::sqrt(t2);
    return -0.5 * std::erfc(a) + std::exp(-a * a) / (2 * a * kSqrtPi);
  }
  Vec3 sample_visible(const Vec3& v, double u1, double u2) const override {
    const double lx = c_ * v.x() + s_ * v.y(), ly = -s_ * v.x() + c_ * v.y();
    Vec3 vs(ax_ * lx, ay_ * ly, v.z());
    vs.normalize();
    const double sin_t = std::hypot(vs.x(), vs.y());
    const double mu = sin_t > 0 ? vs.z() / sin_t : std::numeric_limits<double>::infinity();
    const double cp = sin_t > 0 ? vs.x() / sin_t : 1, sp = sin_t > 0 ? vs.y() / sin_t : 0;
    const double sx1 = legacy_slope(mu, u1);
    const double sy1 = legacy_slope(std::numeric_limits<double>::infinity(), u2);
    const double sx = ax_ * (cp * sx1 - sp * sy1);
    const double sy = ay_ * (sp * sx1 + cp * sy1);
    Vec3 ml(-sx, -sy, 1.0);
    ml.normalize();
    return Vec3(c_ * ml.x() - s_ * ml.y(), s_ * ml.x() + c_ * ml.y(), ml.z());
  }
  std::string describe() const override { return "legacy beckmann"; }

 private:
  double ax_, ay_, c_, s_;
};

// The ellipsoid's previous sampler: the frame across n' = An/|An| built on every call.
Vec3 legacy_hemisphere_visible(const Vec3& v, double u1, double u2) {
  const double lensq = v.x() * v.x() + v.y() * v.y();
  const Vec3 t1 = lensq > 0 ? Vec3(-v.y(), v.x(), 0) / std::sqrt(lensq) : Vec3(1, 0, 0);
  const Vec3 t2 = v.cross(t1);
  const double r = std::sqrt(u1), phi = 2 * kPi * u2;
  const double p1 = r * std::cos(phi);
  double p2 = r * std::sin(phi);
  const double s = 0.5 * (1 + v.z());
  p2 = (1 - s) * std::sqrt(std::max(0.0, 1 - p1 * p1)) + s * p2;
  return p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0, 1 - p1 * p1 - p2 * p2)) * v;
}

class LegacyEllipsoid final : public MicrofacetDistribution {
 public:
  explicit LegacyEllipsoid(const EllipsoidParams& p) : e_(p) {}
  double D(const Vec3& m) const override { return e_.D(m); }
  double lambda(const Vec3& v) const override { return e_.lambda(v); }
  Vec3 sample_visible(const Vec3& v, double u1, double u2) const override {
    const Eigen::Matrix3d& a = e_.A();
    const Vec3 an = a.col(2);
    const Vec3 np = an / an.norm();
    const Vec3 vp = (a * v).normalized();
    const Vec3 helper = std::abs(np.x()) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    const Vec3 b1 = (helper - helper.dot(np) * np).normalized();
    const Vec3 b2 = np.cross(b1);
    const Vec3 vl(vp.dot(b1), vp.dot(b2), vp.dot(np));
    const Vec3 nl = legacy_hemisphere_visible(vl, u1, u2);
    const Vec3 s = nl.x() * b1 + nl.y() * b2 + nl.z() * np;
    return (a.transpose() * s).normalized();
  }
  std::string describe() const override { return "legacy ellipsoid"; }

 private:
  EllipsoidDistribution e_;
};

// ---- inputs ----------------------------------------------------------------------------------
// Views with cos theta uniform (as a path tracer's shading points roughly see them) and uniform
// random numbers; the render's lobe, alpha = (0.08, 0.3).
struct Inputs {
  std::vector<Vec3> v;
  std::vector<double> u;
  std::vector<double> mu;  // cot theta of the stretched views
};
const Inputs& inputs() {
  static const Inputs in = [] {
    Inputs r;
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> un(0, 1);
    for (std::size_t k = 0; k < kBatch; ++k) {
      const double ct = un(rng), st = std::sqrt(1 - ct * ct), p = 2 * kPi * un(rng);
      r.v.emplace_back(st * std::cos(p), st * std::sin(p), ct);
      const double sx = 0.08 * st * std::cos(p), sy = 0.3 * st * std::sin(p);
      r.mu.push_back(ct / std::sqrt(sx * sx + sy * sy));
      r.u.push_back(un(rng));
      r.u.push_back(un(rng));
    }
    return r;
  }();
  return in;
}

std::shared_ptr<MicrofacetDistribution> model(int which) {
  switch (which) {
    case 0:
      return std::make_shared<LegacyBeckmann>(0.08, 0.3, 0);
    case 1:
      return make_distribution(NdfSpec{"beckmann", 0.08, 0.3, 0, 0, 0, 0, {}});
    case 2:
      return make_distribution(NdfSpec{"ggx", 0.08, 0.3, 0, 0, 0, 0, {}});
    case 3:
      return std::make_shared<LegacyEllipsoid>(EllipsoidParams{0.08, 0.3, 0.07, -0.05, 0.35});
    default:
      return make_distribution(NdfSpec{"ellipsoid", 0.08, 0.3, 0, 0.07, -0.05, 0.35, {}});
  }
}
const char* kModel[] = {"beckmann, previous (yardstick)", "beckmann", "ggx",
                        "ellipsoid, previous (yardstick)", "ellipsoid"};

void per_item(benchmark::State& state) {
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kBatch));
}

void BM_BeckmannSampleVisible(benchmark::State& state) {
  const auto d = model(static_cast<int>(state.range(0)));
  const Inputs& in = inputs();
  for (auto _ : state) {
    Vec3 s = Vec3::Zero();
    for (std::size_t k = 0; k < kBatch; ++k)
      s += d->sample_visible(in.v[k], in.u[2 * k], in.u[2 * k + 1]);
    benchmark::DoNotOptimize(s);
  }
  state.SetLabel(kModel[state.range(0)]);
  per_item(state);
}

void BM_BeckmannLambda(benchmark::State& state) {
  const auto d = model(static_cast<int>(state.range(0)));
  const Inputs& in = inputs();
  for (auto _ : state) {
    double s = 0;
    for (const auto& v : in.v) s += d->lambda(v);
    benchmark::DoNotOptimize(s);
  }
  state.SetLabel(kModel[state.range(0)]);
  per_item(state);
}

void BM_BeckmannD(benchmark::State& state) {
  const auto d = model(static_cast<int>(state.range(0)));
  const Inputs& in = inputs();
  for (auto _ : state) {
    double s = 0;
    for (const auto& v : in.v) s += d->D(v);
    benchmark::DoNotOptimize(s);
  }
  state.SetLabel(kModel[state.range(0)]);
  per_item(state);
}

void BM_BeckmannPdfVisible(benchmark::State& state) {
  const auto d = model(static_cast<int>(state.range(0)));
  const Inputs& in = inputs();
  for (auto _ : state) {
    double s = 0;
    for (std::size_t k = 0; k < kBatch; ++k)
      s += d->pdf_visible(in.v[k], in.v[(k * 7 + 1) % kBatch]);
    benchmark::DoNotOptimize(s);
  }
  state.SetLabel(kModel[state.range(0)]);
  per_item(state);
}

// The two slope quantiles alone: 0 = previous, 1 = library.
void BM_BeckmannSlopeX(benchmark::State& state) {
  const Inputs& in = inputs();
  const bool lib = state.range(0) == 1;
  for (auto _ : state) {
    double s = 0;
    for (std::size_t k = 0; k < kBatch; ++k)
      s += lib ? beckmann::visible_slope(in.mu[k], in.u[2 * k])
               : legacy_slope(in.mu[k], in.u[2 * k]);
    benchmark::DoNotOptimize(s);
  }
  state.SetLabel(lib ? "visible slope (mu), library" : "visible slope (mu), previous");
  per_item(state);
}

void BM_BeckmannSlopeY(benchmark::State& state) {
  const Inputs& in = inputs();
  const bool lib = state.range(0) == 1;
  constexpr double inf = std::numeric_limits<double>::infinity();
  for (auto _ : state) {
    double s = 0;
    for (std::size_t k = 0; k < kBatch; ++k)
      s += lib ? beckmann::gauss_quantile(in.u[2 * k + 1]) : legacy_slope(inf, in.u[2 * k + 1]);
    benchmark::DoNotOptimize(s);
  }
  state.SetLabel(lib ? "gaussian slope, library" : "gaussian slope, previous");
  per_item(state);
}

void BM_Erfc(benchmark::State& state) {
  std::vector<double> x(kBatch);
  for (std::size_t k = 0; k < kBatch; ++k) x[k] = -3 + 9.0 * k / kBatch;
  const bool lib = state.range(0) == 1;
  for (auto _ : state) {
    double s = 0;
    for (double v : x) s += lib ? beckmann::erfc(v) : std::erfc(v);
    benchmark::DoNotOptimize(s);
  }
  state.SetLabel(lib ? "beckmann::erfc" : "std::erfc");
  per_item(state);
}

// The start of the visible-slope iteration alone (C(mu), the Gaussian quantile, the table).
void BM_BeckmannSlopeStart(benchmark::State& state) {
  const Inputs& in = inputs();
  for (auto _ : state) {
    double s = 0;
    for (std::size_t k = 0; k < kBatch; ++k)
      s += beckmann::visible_slope_start(in.mu[k], in.u[2 * k]);
    benchmark::DoNotOptimize(s);
  }
  state.SetLabel("visible slope start, library");
  per_item(state);
}

// Smith's Lambda from a = 1/(alpha tan theta) alone (here a = the views' mu).
void BM_BeckmannSmithLambda(benchmark::State& state) {
  const Inputs& in = inputs();
  for (auto _ : state) {
    double s = 0;
    for (std::size_t k = 0; k < kBatch; ++k) s += beckmann::smith_lambda(in.mu[k]);
    benchmark::DoNotOptimize(s);
  }
  state.SetLabel("beckmann::smith_lambda(a)");
  per_item(state);
}

}  // namespace

BENCHMARK(BM_BeckmannSampleVisible)->DenseRange(0, 4);
BENCHMARK(BM_BeckmannLambda)->DenseRange(0, 4);
BENCHMARK(BM_BeckmannD)->DenseRange(0, 4);
BENCHMARK(BM_BeckmannPdfVisible)->DenseRange(0, 4);
BENCHMARK(BM_BeckmannSlopeX)->DenseRange(0, 1);
BENCHMARK(BM_BeckmannSlopeY)->DenseRange(0, 1);
BENCHMARK(BM_Erfc)->DenseRange(0, 1);
BENCHMARK(BM_BeckmannSlopeStart);
BENCHMARK(BM_BeckmannSmithLambda);
