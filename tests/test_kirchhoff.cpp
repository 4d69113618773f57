// Kirchhoff distribution D_K (issue 5): the building blocks and the fast method against the
// direct-summation reference.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <complex>
#include <cstring>
#include <random>

#include "core/fft.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/generate.hpp"
#include "microbrdf/kirchhoff.hpp"
#include "microbrdf/ndf_estimate.hpp"
#include "ndf/kirchhoff_transform.hpp"

using namespace microbrdf;

namespace {

Surface gaussian(std::size_t nx, std::size_t ny, double dx, double sigma, double tau,
                 std::uint64_t seed = 1) {
  GaussianSurfaceParams p;
  p.nx = nx;
  p.ny = ny;
  p.dx = p.dy = dx;
  p.sigma = sigma;
  p.tau_x = p.tau_y = tau;
  p.seed = seed;
  return generate_gaussian(p);
}

// Relative L1 error of the fast table against the direct sums on `count` random disk nodes.
double fast_vs_direct(const KirchhoffPatch& p, double lambda_q, std::size_t n, double accuracy,
                      std::size_t count, std::uint64_t seed, KirchhoffFastInfo* info = nullptr,
                      bool chirp_z = false) {
  auto fast = kirchhoff_table_fast(p, lambda_q, n, accuracy, info, chirp_z);
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::size_t> pick(0, n * n - 1);
  std::vector<std::size_t> nodes;
  while (nodes.size() < count) {
    std::size_t k = pick(rng);
    Eigen::Vector3d q = kirchhoff_node_q(n, k % n, k / n, lambda_q);
    if (q.z() > 0) nodes.push_back(k);
  }
  auto direct = kirchhoff_nodes_direct(p, lambda_q, n, nodes);
  double num = 0, den = 0;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    num += std::fabs(fast[nodes[i]] - direct[i]);
    den += std::fabs(direct[i]);
  }
  return num / den;
}

}  // namespace

TEST(kirchhoff, BesselMatchesStd) {
  for (double x : {1e-6, 0.3, 1.0, 7.5, 42.0, 120.0}) {
    auto j = bessel_j_all(200, x);
    for (unsigned n : {0u, 1u, 2u, 5u, 17u, 60u, 150u}) {
      double ref = std::cyl_bessel_j(static_cast<double>(n), x);
      EXPECT_NEAR(j[n], ref, 1e-13 + 1e-11 * std::fabs(ref)) << "n=" << n << " x=" << x;
    }
  }
}

namespace {

// One axis of the fast D_K's separable transform (ndf/kirchhoff_transform.hpp), run on `batch`
// input vectors of n as kirchhoff_fast.cpp runs it: inputs times factor(j) at position(j), the
// FFT(s), then the weighted tap sums; output k of vector b at [b * m + k].
std::vector<std::complex<double>> run_axis(detail::KirchhoffAxis::Kind kind, std::size_t n,
                                           std::size_t m, double w0, double dw, int taps,
                                           std::size_t batch,
                                           const std::vector<std::complex<double>>& in) {
  const auto ax = detail::KirchhoffAxis::get(kind, n, m, w0, dw, taps, batch);
  detail::KirchhoffAxis::Scratch s;
  ax->prepare(s);
  for (std::size_t b = 0; b < batch; ++b)
    for (std::size_t j = 0; j < n; ++j)
      s.in[b * ax->in_stride() + ax->position(j)] = in[b * n + j] * ax->factor(j);
  ax->run(s);
  std::vector<std::complex<double>> out(batch * m);
  for (std::size_t b = 0; b < batch; ++b)
    for (std::size_t k = 0; k < m; ++k)
      for (std::size_t t = 0; t < ax->taps(); ++t)
        out[b * m + k] += ax->weight(k)[t] * s.out[b * ax->out_stride() + ax->start(k) + t];
  return out;
}

// The DTFT X_b[k] = sum_j x_b[j] exp(-i (w0 + k dw) j) by direct sums.
std::vector<std::complex<double>> dtft(std::size_t n, std::size_t m, double w0, double dw,
                                       std::size_t batch,
                                       const std::vector<std::complex<double>>& in) {
  std::vector<std::complex<double>> ref(batch * m);
  for (std::size_t b = 0; b < batch; ++b)
    for (std::size_t k = 0; k < m; ++k)
      for (std::size_t j = 0; j < n; ++j)
        ref[b * m + k] += in[b * n + j] * std::polar(1.0, -(w0 + dw * static_cast<double>(k)) *
                                                              static_cast<double>(j));
  return ref;
}

std::vector<std::complex<double>> random_vectors(std::size_t count, unsigned seed) {
  std::vector<std::complex<double>> v(count);
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  for (auto& z : v) z = {g(rng), g(rng)};
  return v;
}

}  // namespace

TEST(kirchhoff, ChirpZAxisEqualsDtft) {
  // Exact up to the post-chirp, a factor of modulus 1 per output that D_K = |I|^2 never needs:
  // the moduli agree, and the factor is the same for every vector (so sums over vectors and
  // input arrays that meet at an output keep their relative phases).
  const std::size_t n = 37, m = 53, batch = 3;
  const double w0 = -1.3, dw = 0.0417;
  const auto in = random_vectors(batch * n, 3);
  const auto out = run_axis(detail::KirchhoffAxis::Kind::ChirpZ, n, m, w0, dw, 0, batch, in);
  const auto ref = dtft(n, m, w0, dw, batch, in);
  for (std::size_t k = 0; k < m; ++k) {
    const std::complex<double> f = out[k] / ref[k];
    EXPECT_NEAR(std::abs(f), 1.0, 1e-11) << k;
    for (std::size_t b = 0; b < batch; ++b)
      EXPECT_LT(std::abs(out[b * m + k] - f * ref[b * m + k]),
                1e-11 * (1 + std::abs(ref[b * m + k])))
          << "vector " << b << ", output " << k;
  }
}

TEST(kirchhoff, NufftAxisMatchesDtftToItsTolerance) {
  // The type-2 NUFFT with K taps: error relative to sum |x| about 10^(1-K) (the accuracy knob
  // asks accuracy / 100 of it), again up to one unit-modulus factor per output (the shift to the
  // centre sample), the same for every vector.
  const std::size_t n = 200, m = 301, batch = 5;
  const double w0 = -2.9, dw = 0.0193;
  const auto in = random_vectors(batch * n, 4);
  double l1 = 0;
  for (const auto& v : in) l1 += std::abs(v);
  const auto ref = dtft(n, m, w0, dw, batch, in);
  const double c = static_cast<double>(n / 2);  // the centre sample the NUFFT is shifted to
  for (int taps : {4, 8, 12}) {
    const auto out = run_axis(detail::KirchhoffAxis::Kind::Nufft, n, m, w0, dw, taps, batch, in);
    double worst = 0;
    for (std::size_t b = 0; b < batch; ++b)
      for (std::size_t k = 0; k < m; ++k) {
        const double w = w0 + dw * static_cast<double>(k);
        worst = std::max(worst, std::abs(out[b * m + k] - std::polar(1.0, w * c) * ref[b * m + k]));
      }
    EXPECT_LT(worst / (l1 / batch), 10 * std::pow(10.0, 1 - taps)) << taps << " taps";
  }
}

TEST(kirchhoff, FlatMirrorIsNormalisedAndPeaksAtNormal) {
  Surface s(64, 48, 0.11e-6, 0.11e-6);
  auto p = make_kirchhoff_patch(s);
  // At q = |q| n: I = q_z * area, D_K = q^2 A / (4 pi^2).
  const double lq = 555e-9, qm = 4 * M_PI / lq, a = p.area_w2;
  EXPECT_NEAR(kirchhoff_dk_direct(p, {0, 0, qm}), qm * qm * a / (4 * M_PI * M_PI),
              1e-9 * qm * qm * a);
  auto t = kirchhoff_table_fast(p, lq, 257, 1e-8);
  TabulatedNdf ndf(257);
  ndf.values() = t;
  // Parseval: the integral over the disk is close to 1 (the sinc^2 tails reach the rim).
  EXPECT_NEAR(ndf.integral(), 1.0, 0.05);
  EXPECT_NEAR(ndf.peak().z(), 1.0, 1e-12);
}

TEST(kirchhoff, FastMatchesDirectOnRoughPatchWithHoles) {
  Surface s = gaussian(96, 80, 0.11e-6, 0.15e-6, 1.0e-6, 7);
  std::mt19937 rng(5);
  std::uniform_int_distribution<std::size_t> pick(0, s.size() - 1);
  for (int k = 0; k < 300; ++k) s.invalidate(pick(rng));
  for (auto w : {KirchhoffWindow::None, KirchhoffWindow::Hann, KirchhoffWindow::Gauss}) {
    auto p = make_kirchhoff_patch(s, 3, 2, 90, 75, w);
    EXPECT_GT(p.invalid, 200u);
    KirchhoffFastInfo info;
    double err = fast_vs_direct(p, 555e-9, 257, 1e-6, 300, 11, &info);
    EXPECT_LT(err, 1e-4) << to_string(w) << " terms " << info.terms;
  }
  // The exact transforms (chirp-z) leave only the Chebyshev tail.
  auto p = make_kirchhoff_patch(s, 3, 2, 90, 75, KirchhoffWindow::None);
  EXPECT_LT(fast_vs_direct(p, 555e-9, 129, 1e-10, 200, 12, nullptr, true), 1e-8);
}

TEST(kirchhoff, FastMatchesDirectAtDefaultAccuracyOnBrushedScan) {
  // Acceptance: fast vs direct within 1 % (relative L1 over random disk nodes), default knob.
  BrushedParams b = brushed_preset("stainless4");
  b.nx = 160;
  b.ny = 120;
  Surface s = generate_brushed(b);
  auto p = make_kirchhoff_patch(s);
  KirchhoffFastInfo info;
  double err = fast_vs_direct(p, 555e-9, 513, KirchhoffOptions{}.accuracy, 300, 21, &info);
  std::printf("stainless4 160x120, 513^2: %zu terms, relative L1 %.3g\n", info.terms, err);
  EXPECT_LT(err, 0.01);
}

TEST(kirchhoff, AccuracyKnobTradesTermsForError) {
  Surface s = gaussian(64, 64, 0.11e-6, 0.3e-6, 1.5e-6, 9);
  auto p = make_kirchhoff_patch(s);
  KirchhoffFastInfo loose, tight;
  double e_loose = fast_vs_direct(p, 555e-9, 129, 1e-2, 300, 3, &loose);
  double e_tight = fast_vs_direct(p, 555e-9, 129, 1e-8, 300, 3, &tight);
  EXPECT_LT(loose.terms, tight.terms);
  EXPECT_LT(e_tight, 1e-6);
  EXPECT_LT(e_loose, 0.05);
  EXPECT_LT(e_tight, e_loose);
}

// The fast table is the same to the bit with one thread or two, for both integration rules and
// both transforms, on a problem large enough for the table to use threads (holes, Hann window).
TEST(kirchhoff, FastTableDoesNotDependOnThreadCount) {
  Surface s = gaussian(40, 30, 0.11e-6, 0.03e-6, 1e-6, 3);
  s.invalidate(s.index(20, 12));
  s.invalidate(s.index(21, 12));
  s.invalidate(s.index(33, 3));
  const auto p = make_kirchhoff_patch(s, KirchhoffWindow::Hann);
  const int saved = omp_get_max_threads();
  for (auto m : {KirchhoffIntegration::Midpoint, KirchhoffIntegration::Exact})
    for (bool chirp : {false, true}) {
      omp_set_num_threads(1);
      const auto one = kirchhoff_table_fast(p, 555e-9, 385, 1e-3, nullptr, chirp, m);
      omp_set_num_threads(2);
      const auto two = kirchhoff_table_fast(p, 555e-9, 385, 1e-3, nullptr, chirp, m);
      ASSERT_EQ(one.size(), two.size());
      EXPECT_EQ(std::memcmp(one.data(), two.data(), one.size() * sizeof(double)), 0)
          << to_string(m) << (chirp ? ", chirp-z" : ", NUFFT");
      double sum = 0;
      for (double v : one) sum += v;
      EXPECT_GT(sum, 0);
    }
  omp_set_num_threads(saved);
}

// Acceptance 4 at full size: one 640 x 480 scan (70.4 x 52.8 um at 110 nm) on the 1025^2 table,
// default accuracy, against the direct sums on 200 random disk nodes.
TEST(kirchhoff, SlowFullScanFastMatchesDirect) {
  BrushedParams b = brushed_preset("stainless4");
  b.nx = 640;
  b.ny = 480;
  Surface s = generate_brushed(b);
  auto p = make_kirchhoff_patch(s);
  KirchhoffFastInfo info;
  double err = fast_vs_direct(p, 555e-9, 1025, KirchhoffOptions{}.accuracy, 200, 5, &info);
  std::printf("640x480 -> 1025^2: %zu terms, relative L1 %.3g\n", info.terms, err);
  EXPECT_LT(err, 0.01);
}
