// Spherical-harmonic BRDF (Westin 1992): the basis evaluators against a brute-force reference in
// the same run (std::sph_legendre / std::assoc_legendre from <cmath> per (l, m), plus cos/sin per
// m), ShBrdf::eval / sample / pdf per second (isotropic and anisotropic sampling tables, table
// built before timing), the one-off table build, and the estimator's add_incident.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/sh_basis.hpp"
#include "microbrdf/sh_brdf.hpp"

using namespace microbrdf;

namespace {

constexpr std::size_t kBatch = 1024;
constexpr double kPi = 3.14159265358979323846;

std::vector<Vec3> directions(unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3> v(kBatch);
  for (auto& d : v) {
    double ct = u(rng), st = std::sqrt(1 - ct * ct), p = 2 * kPi * u(rng);
    d = Vec3(st * std::cos(p), st * std::sin(p), ct);
  }
  return v;
}

void rate(benchmark::State& state, const char* name, double per_iteration = kBatch) {
  state.counters[name] =
      benchmark::Counter(per_iteration, benchmark::Counter::kIsIterationInvariantRate);
}

void BM_ShEval(benchmark::State& state) {
  const int L = static_cast<int>(state.range(0));
  auto w = directions(1);
  std::vector<double> y(sh_count(L));
  for (auto _ : state)
    for (const auto& d : w) {
      sh_eval(L, d, y.data());
      benchmark::DoNotOptimize(y.data());
    }
  rate(state, "dirs/s");
}
BENCHMARK(BM_ShEval)->Arg(15)->Arg(30);

void BM_ShOddBasisEval(benchmark::State& state) {
  const int L = static_cast<int>(state.range(0));
  ShOddBasis b(L);
  auto w = directions(1);
  std::vector<double> y(b.size());
  for (auto _ : state)
    for (const auto& d : w) {
      b.eval(d, y.data());
      benchmark::DoNotOptimize(y.data());
    }
  rate(state, "dirs/s");
}
BENCHMARK(BM_ShOddBasisEval)->Arg(15)->Arg(30);

// The estimator's per-direction projection: sum of weight * Y_j over the exits of one incident
// direction, 16 at a time (four lanes; AVX2 where the CPU has it), against 16 single eval() calls
// and the running sum above.
void BM_ShOddBasisEvalSum(benchmark::State& state) {
  const int L = static_cast<int>(state.range(0));
  ShOddBasis b(L);
  auto w = directions(1);
  std::vector<double> r(kBatch, 0.7), sum(b.size());
  for (auto _ : state)
    for (std::size_t k = 0; k < kBatch; k += 16) {
      b.eval_sum(16, &w[k], &r[k], sum.data());
      benchmark::DoNotOptimize(sum.data());
    }
  rate(state, "dirs/s");
}
BENCHMARK(BM_ShOddBasisEvalSum)->Arg(15)->Arg(30);

// The same sum by single evaluations (what the estimator did before eval_sum).
void BM_ShOddBasisEvalThenSum(benchmark::State& state) {
  const int L = static_cast<int>(state.range(0));
  ShOddBasis b(L);
  auto w = directions(1);
  std::vector<double> y(b.size()), sum(b.size());
  for (auto _ : state)
    for (std::size_t k = 0; k < kBatch; k += 16) {
      std::fill(sum.begin(), sum.end(), 0.0);
      for (std::size_t e = k; e < k + 16; ++e) {
        b.eval(w[e], y.data());
        for (int j = 0; j < b.size(); ++j) sum[j] += 0.7 * y[j];
      }
      benchmark::DoNotOptimize(sum.data());
    }
  rate(state, "dirs/s");
}
BENCHMARK(BM_ShOddBasisEvalThenSum)->Arg(15)->Arg(30);

// The brute-force references: real Y_lm for l <= L at direction d from the normalised
// associated Legendre value p(l, m) (Condon-Shortley phase removed) and the azimuth of d.
template <class Legendre>
void real_sh_brute(int L, const Vec3& d, double* y, Legendre p_lm) {
  const double ph = std::atan2(d.y(), d.x());
  for (int l = 0; l <= L; ++l)
    for (int m = 0; m <= l; ++m) {
      const double p = p_lm(l, m);
      if (m == 0) {
        y[sh_index(l, 0)] = p;
      } else {
        y[sh_index(l, m)] = std::sqrt(2.0) * p * std::cos(m * ph);
        y[sh_index(l, -m)] = std::sqrt(2.0) * p * std::sin(m * ph);
      }
    }
}

// Reference: every Y_lm separately from std::sph_legendre (normalised, CS phase removed).
void BM_ShEvalBruteSphLegendre(benchmark::State& state) {
  const int L = static_cast<int>(state.range(0));
  auto w = directions(1);
  std::vector<double> y(sh_count(L));
  for (auto _ : state)
    for (const auto& d : w) {
      const double th = std::acos(d.z());
      real_sh_brute(L, d, y.data(), [th](int l, int m) {
        return (m % 2 ? -1.0 : 1.0) * std::sph_legendre(l, m, th);
      });
      benchmark::DoNotOptimize(y.data());
    }
  rate(state, "dirs/s");
}
BENCHMARK(BM_ShEvalBruteSphLegendre)->Arg(15)->Arg(30);

// Reference: std::assoc_legendre times K_l^m from lgamma (the textbook formula).
void BM_ShEvalBruteAssocLegendre(benchmark::State& state) {
  const int L = static_cast<int>(state.range(0));
  auto w = directions(1);
  std::vector<double> y(sh_count(L));
  for (auto _ : state)
    for (const auto& d : w) {
      real_sh_brute(L, d, y.data(), [z = d.z()](int l, int m) {
        const double k = std::sqrt((2 * l + 1) / (4 * kPi) *
                                   std::exp(std::lgamma(l - m + 1) - std::lgamma(l + m + 1)));
        return k * std::assoc_legendre(l, m, z);
      });
      benchmark::DoNotOptimize(y.data());
    }
  rate(state, "dirs/s");
}
BENCHMARK(BM_ShEvalBruteAssocLegendre)->Arg(15)->Arg(30);

// A projected GGX lobe (range(1) = 1: anisotropic, rotated), built once per lmax.
const ShBrdf& brdf(int L, bool aniso) {
  static std::vector<std::unique_ptr<ShBrdf>> cache(2 * (kShMaxL + 1));
  auto& p = cache[2 * L + aniso];
  if (!p) {
    MicrofacetBrdf g(std::make_shared<GgxDistribution>(0.3, aniso ? 0.15 : 0.3, aniso ? 0.4 : 0),
                     std::make_shared<PerfectMirrorFresnel>());
    p = std::make_unique<ShBrdf>(ShBrdf::project(g, L, 555e-9, std::min(L + 8, 32)));
  }
  return *p;
}

// kBatch evaluations of b over fixed pairs of directions.
void eval_batch(benchmark::State& state, const ShBrdf& b) {
  auto wi = directions(2), wo = directions(3);
  for (auto _ : state) {
    double s = 0;
    for (std::size_t k = 0; k < kBatch; ++k) s += b.eval(wi[k], wo[k], 555e-9);
    benchmark::DoNotOptimize(s);
  }
  rate(state, "evals/s");
}

void BM_ShBrdfEval(benchmark::State& state) {
  eval_batch(state, brdf(static_cast<int>(state.range(0)), false));
}
BENCHMARK(BM_ShBrdfEval)->Arg(15)->Arg(30);

// One direction bound per 64 evaluations (a shading point with 64 light directions).
void BM_ShBrdfEvalBound(benchmark::State& state) {
  const ShBrdf& b = brdf(static_cast<int>(state.range(0)), false);
  auto wi = directions(2), wo = directions(3);
  for (auto _ : state) {
    double s = 0;
    for (std::size_t k = 0; k < kBatch; k += 64) {
      const auto bound = b.bind(wi[k]);
      for (std::size_t j = k; j < k + 64; ++j) s += b.eval_bound(bound, wo[j]);
    }
    benchmark::DoNotOptimize(s);
  }
  rate(state, "evals/s");
}
BENCHMARK(BM_ShBrdfEvalBound)->Arg(15)->Arg(30);

// The same lobe after isotropic_average(): M is block diagonal in |m|, eval works per block.
void BM_ShBrdfEvalIsotropicBlocks(benchmark::State& state) {
  eval_batch(state, brdf(static_cast<int>(state.range(0)), false).isotropic_average());
}
BENCHMARK(BM_ShBrdfEvalIsotropicBlocks)->Arg(15)->Arg(30);

void BM_ShBrdfSample(benchmark::State& state) {
  const ShBrdf& b = brdf(static_cast<int>(state.range(0)), state.range(1) != 0);
  auto wi = directions(4);
  b.pdf(wi[0], wi[1]);  // build the table outside the timing
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  for (auto _ : state) {
    double s = 0;
    for (const auto& d : wi)
      if (auto smp = b.sample(d, u(rng), u(rng), 555e-9)) s += smp->weight;
    benchmark::DoNotOptimize(s);
  }
  rate(state, "samples/s");
}
BENCHMARK(BM_ShBrdfSample)->Args({15, 0})->Args({15, 1})->Args({30, 0})->Args({30, 1});

void BM_ShBrdfPdf(benchmark::State& state) {
  const ShBrdf& b = brdf(static_cast<int>(state.range(0)), state.range(1) != 0);
  auto wi = directions(6), wo = directions(7);
  b.pdf(wi[0], wi[1]);
  for (auto _ : state) {
    double s = 0;
    for (std::size_t k = 0; k < kBatch; ++k) s += b.pdf(wi[k], wo[k]);
    benchmark::DoNotOptimize(s);
  }
  rate(state, "pdfs/s");
}
BENCHMARK(BM_ShBrdfPdf)->Args({30, 0})->Args({30, 1});

// One-off: the sampling table (a fresh copy of M each iteration, so the table is rebuilt).
void BM_ShBrdfTableBuild(benchmark::State& state) {
  const ShBrdf& src = brdf(static_cast<int>(state.range(0)), state.range(1) != 0);
  for (auto _ : state) {
    ShBrdf b(src.lmax(), src.matrix());
    benchmark::DoNotOptimize(b.pdf(Vec3(0, 0, 1), Vec3(0, 0, 1)));
  }
  rate(state, "tables/s", 1);
}
BENCHMARK(BM_ShBrdfTableBuild)
    ->Args({15, 0})
    ->Args({15, 1})
    ->Args({30, 0})
    ->Args({30, 1})
    ->Unit(benchmark::kMillisecond);

// add_incident with one precomputed exit sum: the O(size^2) outer product per incident direction,
// batched 64 at a time into one register-tiled rank-64 update
// (the tracer's cost per exit is one ShOddBasis::eval, benchmarked above).
void BM_ShEstimatorAddIncident(benchmark::State& state) {
  const int L = static_cast<int>(state.range(0));
  ShEstimator e(L);
  auto w = directions(8);
  std::vector<double> sum(e.basis().size());
  e.basis().eval(w[1], sum.data());
  std::size_t k = 0;
  for (auto _ : state) {
    const Vec3& u = w[k++ % kBatch];
    e.add_incident(u, u.z() / kPi, sum.data(), 64, 0.5);
  }
  benchmark::DoNotOptimize(e.raw()(0, 0));
  rate(state, "incident/s", 1);
}
BENCHMARK(BM_ShEstimatorAddIncident)->Arg(15)->Arg(30);

}  // namespace
