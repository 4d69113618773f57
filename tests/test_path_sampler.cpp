// The renderer's path sampler (src/render/path_sampler.hpp): stratification of the scrambled
// Sobol' points per pixel, uniformity over pixels, determinism, and the environment
// distribution's monotone inversion that carries the stratification to the sphere.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include "render/distribution2d.hpp"
#include "render/path_sampler.hpp"

using microbrdf::pt::PathSampler;
using microbrdf::pt::PathSamplerKind;

namespace {

// The points of request number `request` (1-based, all of them 2D) of the spp samples of a pixel.
std::vector<std::pair<double, double>> pixel_points(PathSamplerKind kind, std::uint64_t pixel,
                                                    int spp, int request) {
  std::vector<std::pair<double, double>> p;
  for (int s = 0; s < spp; ++s) {
    PathSampler ps(kind, 7, pixel, std::uint32_t(s), std::uint32_t(spp));
    double u1 = 0, u2 = 0;
    for (int r = 0; r < request; ++r) ps.get2d(u1, u2);
    p.emplace_back(u1, u2);
  }
  return p;
}

// True when each elementary interval [i/2^a, (i+1)/2^a) x [j/2^b, (j+1)/2^b), a + b = m, holds
// exactly one of the 2^m points: the (0,m,2)-net property.
bool is_net(const std::vector<std::pair<double, double>>& p, int m) {
  for (int a = 0; a <= m; ++a) {
    const int b = m - a;
    std::set<long> seen;
    for (const auto& [x, y] : p) {
      const long i = long(std::ldexp(x, a)), j = long(std::ldexp(y, b));
      if (!seen.insert(i * (1L << b) + j).second) return false;
    }
  }
  return true;
}

}  // namespace

TEST(PathSampler, SobolDimensionOneIsTheKnownSequence) {
  // Second Sobol' dimension in index (not Gray-code) order: direction numbers 1/2, 3/4, 5/8,
  // so points 0, 1/2, 3/4, 1/4, 5/8, 1/8, 3/8, 7/8.
  const double want[] = {0, 0.5, 0.75, 0.25, 0.625, 0.125, 0.375, 0.875};
  for (std::uint32_t i = 0; i < 8; ++i)
    EXPECT_EQ(PathSampler::sobol_dim1(i) * 0x1.0p-32, want[i]) << i;
  EXPECT_EQ(PathSampler::reverse_bits(1u), 0x80000000u);
  EXPECT_EQ(PathSampler::reverse_bits(6u), 0x60000000u);
}

TEST(PathSampler, BitReversalMatchesTheDefinition) {
  // Bit k goes to bit 31 - k, for single bits and for mixed words; and the scramble of a reversed
  // index skips the two reversals that cancel without changing the value.
  for (int k = 0; k < 32; ++k) EXPECT_EQ(PathSampler::reverse_bits(1u << k), 1u << (31 - k)) << k;
  std::uint32_t x = 0x9E3779B9u;
  for (int n = 0; n < 1000; ++n) {
    x = x * 1664525u + 1013904223u;
    std::uint32_t r = 0;
    for (int k = 0; k < 32; ++k) r |= ((x >> k) & 1u) << (31 - k);
    ASSERT_EQ(PathSampler::reverse_bits(x), r) << x;
    EXPECT_EQ(PathSampler::owen_of_reversed(x, r), PathSampler::owen(r, r));
  }
}

TEST(PathSampler, ScrambleAndShuffleArePermutations) {
  // The Owen scramble maps the 2^m intervals of width 2^-m onto themselves (a permutation of the
  // leading m bits); the index shuffle permutes [0, 2^m) for every m.
  for (std::uint32_t seed : {0u, 1u, 0xDEADBEEFu, 123456789u}) {
    for (int m : {1, 4, 8}) {
      std::set<std::uint32_t> lead, idx;
      for (std::uint32_t i = 0; i < (1u << m); ++i) {
        lead.insert(PathSampler::owen(i << (32 - m), seed) >> (32 - m));
        idx.insert(PathSampler::shuffle(i, seed, m));
      }
      EXPECT_EQ(lead.size(), 1u << m);
      EXPECT_EQ(idx.size(), 1u << m);
    }
  }
}

TEST(PathSampler, SobolPointsOfAPixelFormANetInEveryRequest) {
  // For spp = 2^m every 2D request of a pixel is a (0,m,2)-net: stratified in every aspect
  // ratio. Independent points are not (checked so that the test can fail).
  for (int m : {2, 4, 6}) {
    const int spp = 1 << m;
    for (std::uint64_t pixel : {0ull, 17ull, 90001ull})
      for (int request = 1; request <= 4; ++request)
        EXPECT_TRUE(is_net(pixel_points(PathSamplerKind::Sobol, pixel, spp, request), m))
            << "m " << m << " pixel " << pixel << " request " << request;
  }
  int nets = 0;
  for (std::uint64_t pixel = 0; pixel < 20; ++pixel)
    nets += is_net(pixel_points(PathSamplerKind::Independent, pixel, 16, 1), 4);
  EXPECT_LT(nets, 2);
}

TEST(PathSampler, OneDimensionalRequestsAreStratified) {
  // 16 samples of a 1D request: one in each sixteenth.
  for (std::uint64_t pixel : {3ull, 4ull}) {
    std::set<int> bins;
    for (int s = 0; s < 16; ++s) {
      PathSampler ps(PathSamplerKind::Sobol, 1, pixel, std::uint32_t(s), 16);
      double a, b;
      ps.get2d(a, b);
      bins.insert(int(ps.get1d() * 16));
    }
    EXPECT_EQ(bins.size(), 16u);
  }
}

TEST(PathSampler, ValuesAreUniformOverPixelsAndRequestsAreIndependent) {
  // One value per pixel (the first sample): over 40000 pixels the mean is 1/2, the fraction
  // below 0.3 is 0.3, and two different requests are uncorrelated (each within 5 sigma), so the
  // scramble randomises and the padding decorrelates.
  const int n = 40000;
  double mean = 0, below = 0, cov = 0;
  for (int p = 0; p < n; ++p) {
    PathSampler ps(PathSamplerKind::Sobol, 3, std::uint64_t(p), 5, 64);
    double a, b;
    ps.get2d(a, b);
    const double c = ps.get1d();
    mean += a;
    below += b < 0.3;
    cov += (a - 0.5) * (c - 0.5);
  }
  EXPECT_NEAR(mean / n, 0.5, 5 * std::sqrt(1.0 / 12 / n));
  EXPECT_NEAR(below / n, 0.3, 5 * std::sqrt(0.21 / n));
  EXPECT_NEAR(cov / n, 0.0, 5 * (1.0 / 12) / std::sqrt(double(n)));
}

TEST(PathSampler, RequestsOfAPixelAreUncorrelated) {
  // Over the 64 samples of a pixel, the numbers of different requests (jitter x, jitter y,
  // wavelength, light u1, light u2) are uncorrelated: the mean squared correlation over 400
  // pixels is near 1/63 (what independent sets give), far from the 0.5 that a shared first
  // digit would give.
  const int spp = 64, pixels = 400;
  double sum_r2 = 0;
  int pairs = 0;
  for (int p = 0; p < pixels; ++p) {
    std::vector<std::vector<double>> v(5, std::vector<double>(spp));
    for (int s = 0; s < spp; ++s) {
      PathSampler ps(PathSamplerKind::Sobol, 1, std::uint64_t(p), std::uint32_t(s), spp);
      ps.get2d(v[0][s], v[1][s]);
      v[2][s] = ps.get1d();
      ps.get2d(v[3][s], v[4][s]);
    }
    for (int a = 0; a < 5; ++a)
      for (int b = a + 1; b < 5; ++b) {
        if (a == 0 && b == 1) continue;  // the two halves of one 2D request: a net, not random
        if (a == 3 && b == 4) continue;
        double c = 0;
        for (int s = 0; s < spp; ++s) c += (v[a][s] - 0.5) * (v[b][s] - 0.5);
        const double r = c / spp * 12;  // each set is stratified: variance 1/12 exactly enough
        sum_r2 += r * r;
        ++pairs;
      }
  }
  EXPECT_LT(sum_r2 / pairs, 2.0 / (spp - 1));
}

TEST(PathSampler, SameArgumentsSameNumbers) {
  PathSampler a(PathSamplerKind::Sobol, 9, 1234, 7, 64), b(PathSamplerKind::Sobol, 9, 1234, 7, 64);
  PathSampler c(PathSamplerKind::Sobol, 10, 1234, 7, 64);
  double a1, a2, b1, b2, c1, c2;
  a.get2d(a1, a2);
  b.get2d(b1, b2);
  c.get2d(c1, c2);
  EXPECT_EQ(a1, b1);
  EXPECT_EQ(a2, b2);
  EXPECT_EQ(a.get1d(), b.get1d());
  EXPECT_NE(a1, c1);  // another seed, other numbers
}

TEST(PathSampler, EnvironmentInversionIsMonotoneAndKeepsStrata) {
  // Row choice grows with u2 and the position within a row with u1; 16 stratified points over a
  // 4 x 4 grid of equal weights land one per cell.
  std::vector<double> w(16, 1.0);
  w[5] = 0;  // an empty cell is never chosen
  w[6] = 3;
  const microbrdf::pt::PiecewiseConstant2D d(w, 4, 4);
  double last_v = -1;
  for (int k = 0; k < 200; ++k) {
    double u, v, pdf;
    d.sample(0.3, (k + 0.5) / 200, u, v, pdf);
    EXPECT_GE(v, last_v);
    last_v = v;
    EXPECT_GT(pdf, 0);
  }
  double last_u = -1;
  for (int k = 0; k < 200; ++k) {
    double u, v, pdf;
    d.sample((k + 0.5) / 200, 0.4, u, v, pdf);
    EXPECT_GE(u, last_u);
    last_u = u;
    EXPECT_NE(int(v * 4) * 4 + int(u * 4), 5);
  }
  const microbrdf::pt::PiecewiseConstant2D flat(std::vector<double>(16, 1.0), 4, 4);
  std::set<int> cells;
  for (const auto& [x, y] : pixel_points(PathSamplerKind::Sobol, 11, 16, 2)) {
    double u, v, pdf;
    cells.insert(int(flat.sample(x, y, u, v, pdf)));
  }
  EXPECT_EQ(cells.size(), 16u);
}

TEST(PathSampler, EnvironmentInversionMatchesBinarySearch) {
  // The guide tables only say where a search starts: the cell and the position within it are
  // those of a plain binary search of the running sums, for skewed weights with empty runs, a
  // single bright cell and numbers next to the strata edges.
  const std::size_t nu = 37, nv = 23;
  std::vector<double> w(nu * nv);
  std::uint64_t s = 12345;
  auto next = [&s] {
    s = s * 6364136223846793005ULL + 1442695040888963407ULL;
    return double(s >> 11) * 0x1.0p-53;
  };
  for (std::size_t i = 0; i < w.size(); ++i) {
    const double r = next();
    w[i] = r < 0.3 ? 0.0 : std::pow(r, 12.0);
  }
  for (std::size_t c = 0; c < nu; ++c) w[4 * nu + c] = 0;  // an empty row
  w[9 * nu + 3] = 1e4;                                     // a sun
  const microbrdf::pt::PiecewiseConstant2D d(w, nu, nv);
  std::vector<double> rows(nv + 1, 0.0), cols((nu + 1) * nv, 0.0);
  for (std::size_t r = 0; r < nv; ++r) {
    for (std::size_t c = 0; c < nu; ++c)
      cols[r * (nu + 1) + c + 1] = cols[r * (nu + 1) + c] + w[r * nu + c];
    rows[r + 1] = rows[r] + cols[r * (nu + 1) + nu];
  }
  auto find = [](const double* c, std::size_t m, double x) {
    const double t = x * c[m];
    std::size_t k = std::size_t(std::upper_bound(c, c + m + 1, t) - c);
    k = std::clamp<std::size_t>(k, 1, m) - 1;
    while (k + 1 < m && !(c[k + 1] > c[k])) ++k;
    while (k > 0 && !(c[k + 1] > c[k])) --k;
    return k;
  };
  std::vector<double> xs;
  for (int k = 0; k < 4000; ++k) xs.push_back(next());
  for (std::size_t j = 0; j <= 64; ++j) {  // on and next to the guide's own points
    const double g = double(j) / 64;
    for (double x : {g, std::nextafter(g, 0.0), std::nextafter(g, 1.0)})
      if (x >= 0 && x < 1) xs.push_back(x);
  }
  for (std::size_t i = 0; i + 1 < xs.size(); ++i) {
    const double u1 = xs[i], u2 = xs[xs.size() - 1 - i];
    double u, v, pdf;
    const std::size_t cell = d.sample(u1, u2, u, v, pdf);
    const std::size_t row = find(rows.data(), nv, u2);
    const std::size_t col = find(&cols[row * (nu + 1)], nu, u1);
    ASSERT_EQ(cell, row * nu + col) << "u1 " << u1 << " u2 " << u2;
    EXPECT_GT(w[cell], 0);
  }
}

TEST(PathSampler, SobolDimensionOneTablesMatchTheLoop) {
  // The byte tables give the direction-number XOR of the plain loop for every index.
  std::uint64_t s = 5;
  for (int k = 0; k < 100000; ++k) {
    s = s * 6364136223846793005ULL + 1442695040888963407ULL;
    const auto i = std::uint32_t(s >> 32) >> (k % 32);
    ASSERT_EQ(PathSampler::sobol_dim1(i), PathSampler::sobol_dim1_loop(i)) << i;
  }
  for (std::uint32_t i = 0; i < 70000; ++i)
    ASSERT_EQ(PathSampler::sobol_dim1(i), PathSampler::sobol_dim1_loop(i)) << i;
}

TEST(PathSampler, SharedPixelHashesGiveTheSameNumbers) {
  // The pixel's request hashes made once (PixelHashes) and per sample: the same numbers, 1D and
  // 2D requests mixed, past the cached range, for both kinds; the reversed Sobol' tables are the
  // reversed values.
  for (auto kind : {PathSamplerKind::Sobol, PathSamplerKind::Independent})
    for (std::uint64_t pixel : {0ull, 5ull, 123456789ull}) {
      microbrdf::pt::PixelHashes hashes(11, pixel);
      for (std::uint32_t s = 0; s < 24; ++s) {
        PathSampler a(kind, 11, pixel, s, 24), b(kind, hashes, s, 24);
        for (int r = 0; r < 80; ++r) {
          if ((r + s) % 3 == 0) {
            ASSERT_EQ(a.get1d(), b.get1d()) << r;
          } else {
            double a1, a2, b1, b2;
            a.get2d(a1, a2);
            b.get2d(b1, b2);
            ASSERT_EQ(a1, b1) << r;
            ASSERT_EQ(a2, b2) << r;
          }
        }
      }
    }
  for (std::uint32_t i : {0u, 1u, 2u, 77u, 0x12345678u, 0xFFFFFFFFu})
    EXPECT_EQ(PathSampler::sobol_dim1_reversed(i),
              PathSampler::reverse_bits(PathSampler::sobol_dim1(i)));
}
