// D_K by exact integration over the triangles of the piecewise-linear surface: the closed form
// (second divided difference of exp) against brute-force quadrature written independently here,
// the fast table against both, and the integral of D_K before normalising.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <random>
#include <vector>

#include "microbrdf/generate.hpp"
#include "microbrdf/kirchhoff.hpp"

using namespace microbrdf;
using cd = std::complex<double>;

namespace {

// Gauss-Legendre on [0, 1] from std::legendre (Newton with P_n' = n (x P_n - P_{n-1})/(x^2 - 1)).
struct Gauss {
  std::vector<double> x, w;
  explicit Gauss(unsigned n) {
    for (unsigned i = 0; i < n; ++i) {
      double t = std::cos(M_PI * (i + 0.75) / (n + 0.5)), d = 1;
      for (int it = 0; it < 60; ++it) {
        d = n * (t * std::legendre(n, t) - std::legendre(n - 1, t)) / (t * t - 1);
        double step = std::legendre(n, t) / d;
        t -= step;
        if (std::fabs(step) < 1e-15) break;
      }
      x.push_back(0.5 * (t + 1));
      w.push_back(1.0 / ((1 - t * t) * d * d));
    }
  }
};

// Integral of f over the triangle with corners P0, P1, P2 (2-D), Duffy-collapsed n x n rule.
template <class F>
cd triangle_quadrature(const double* p0, const double* p1, const double* p2, F f, unsigned n) {
  static const Gauss g(24);
  (void)n;
  const double e1[2] = {p1[0] - p0[0], p1[1] - p0[1]}, e2[2] = {p2[0] - p0[0], p2[1] - p0[1]};
  const double jac = std::fabs(e1[0] * e2[1] - e1[1] * e2[0]);
  cd sum = 0;
  for (std::size_t i = 0; i < g.x.size(); ++i)
    for (std::size_t j = 0; j < g.x.size(); ++j) {
      const double s = g.x[i], t = (1 - s) * g.x[j];  // s in [0,1], t in [0, 1-s]
      const double x = p0[0] + s * e1[0] + t * e2[0], y = p0[1] + s * e1[1] + t * e2[1];
      sum += g.w[i] * g.w[j] * (1 - s) * f(x, y);
    }
  return sum * jac;
}

// Brute force D_K of the piecewise-linear surface through the samples of `s`: for every
// triangle (cells split along the (ix,iy)-(ix+1,iy+1) diagonal, all three corners valid), the
// plane through its corners, and the integral of w (q_z - q_x h_x - q_y h_y) exp(-i q.(x,y,h))
// over its projection by quadrature. No window (w = 1).
double brute_force_dk(const Surface& s, const Eigen::Vector3d& q) {
  cd total = 0;
  double area = 0;
  auto corner = [&](std::size_t x, std::size_t y, double* out) {
    out[0] = s.dx * static_cast<double>(x);
    out[1] = s.dy * static_cast<double>(y);
    out[2] = s.at(x, y);
    return s.valid[s.index(x, y)] != 0;
  };
  for (std::size_t y = 0; y + 1 < s.ny; ++y)
    for (std::size_t x = 0; x + 1 < s.nx; ++x) {
      double c[4][3];
      bool ok00 = corner(x, y, c[0]), ok10 = corner(x + 1, y, c[1]), ok01 = corner(x, y + 1, c[2]),
           ok11 = corner(x + 1, y + 1, c[3]);
      const int tris[2][3] = {{0, 1, 3}, {0, 3, 2}};
      const bool ok[2] = {ok00 && ok10 && ok11, ok00 && ok11 && ok01};
      for (int t = 0; t < 2; ++t) {
        if (!ok[t]) continue;
        const double *a = c[tris[t][0]], *b = c[tris[t][1]], *d = c[tris[t][2]];
        // Plane h = a_z + gx (x - a_x) + gy (y - a_y) through the three corners (normal by the
        // cross product of two edges).
        const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]},
                     v[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
        const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                             u[0] * v[1] - u[1] * v[0]};
        const double gx = -n[0] / n[2], gy = -n[1] / n[2];
        const double qm = q.z() - q.x() * gx - q.y() * gy;
        auto f = [&](double px, double py) {
          const double h = a[2] + gx * (px - a[0]) + gy * (py - a[1]);
          return qm * std::polar(1.0, -(q.x() * px + q.y() * py + q.z() * h));
        };
        total += triangle_quadrature(a, b, d, f, 24);
        area += 0.5 * std::fabs(n[2]);
      }
    }
  return std::norm(total) / (4 * M_PI * M_PI * area);
}

// exp[z0, z1, z2] by quadrature over the standard triangle.
cd dd_quadrature(cd z0, cd z1, cd z2) {
  const double p0[2] = {0, 0}, p1[2] = {1, 0}, p2[2] = {0, 1};
  return triangle_quadrature(
      p0, p1, p2, [&](double a, double b) { return std::exp(z0 + a * (z1 - z0) + b * (z2 - z0)); },
      24);
}

Surface rough_patch(std::size_t nx, std::size_t ny, double sigma, double tau, std::uint64_t seed) {
  GaussianSurfaceParams g;
  g.nx = nx;
  g.ny = ny;
  g.dx = g.dy = 0.11e-6;
  g.sigma = sigma;
  g.tau_x = g.tau_y = tau;
  g.seed = seed;
  return generate_gaussian(g);
}

}  // namespace

TEST(kirchhoff_exact, DividedDifferenceMatchesQuadratureIncludingDegenerateCases) {
  const cd i(0, 1);
  struct Case {
    cd z0, z1, z2;
  };
  std::vector<Case> cases = {
      {0.0, 0.0, 0.0},                                    // all coincident: 1/2
      {1.3 * i, 1.3 * i, 1.3 * i},                        // e^z / 2
      {0.2 * i, 0.2 * i, -0.7 * i},                       // two coincident
      {0.5 * i, 0.5 * i + 1e-9 * i, 2.0 * i},             // two nearly coincident, far third
      {3.0 * i, 3.0 * i + 1e-7 * i, 3.0 * i - 2e-7 * i},  // all nearly coincident
      {-0.6 * i, 0.35 * i, 0.25 * i},                     // spread just below the series threshold
      {-0.8 * i, 0.45 * i, 0.35 * i},                     // just above
      {0.0, 2.5 * i, 3.5 * i},                            // a cell at the rim of the disk
      {-4.0 * i, 1.0 * i, 6.0 * i},                       // steep triangle
      {0.3 + 0.1 * i, -0.2 + 0.4 * i, 0.1 - 0.3 * i},     // general complex points
  };
  for (const auto& c : cases) {
    const cd got = exp_divided_difference(c.z0, c.z1, c.z2), ref = dd_quadrature(c.z0, c.z1, c.z2);
    EXPECT_LT(std::abs(got - ref), 1e-13 * std::max(1.0, std::abs(ref)))
        << c.z0 << " " << c.z1 << " " << c.z2 << ": " << got << " vs " << ref;
    // Symmetric in its arguments.
    EXPECT_LT(std::abs(exp_divided_difference(c.z2, c.z0, c.z1) - got), 1e-14);
  }
  // Well separated points: the textbook sum over the corners.
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-20, 20);
  for (int k = 0; k < 50; ++k) {
    cd z[3] = {cd(0, u(rng)), cd(0, u(rng)), cd(0, u(rng))};
    cd ref = 0;
    for (int a = 0; a < 3; ++a) {
      cd den = 1;
      for (int b = 0; b < 3; ++b)
        if (b != a) den *= z[a] - z[b];
      ref += std::exp(z[a]) / den;
    }
    if (std::abs(z[0] - z[1]) < 0.5 || std::abs(z[1] - z[2]) < 0.5 || std::abs(z[0] - z[2]) < 0.5)
      continue;  // the textbook form itself cancels there
    EXPECT_LT(std::abs(exp_divided_difference(z[0], z[1], z[2]) - ref), 1e-12);
  }
}

// Acceptance: exact-triangle D_K equals the brute-force integral of the same piecewise-linear
// surface to 1e-6, directly and through the fast table, on a small rough patch with a hole.
TEST(kirchhoff_exact, ExactDkEqualsBruteForceOnSmallPatch) {
  Surface s = rough_patch(12, 10, 0.06e-6, 0.4e-6, 3);  // rms slope ~0.2, steep triangles
  s.invalidate(s.index(5, 4));
  const KirchhoffPatch p = make_kirchhoff_patch(s);
  EXPECT_EQ(p.triangles, 2u * 11u * 9u - 6u);  // the hole removes its six triangles
  const double lq = 555e-9;
  const std::size_t N = 65;
  std::vector<std::size_t> nodes;
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<std::size_t> pick(0, N * N - 1);
  nodes.push_back((N / 2) * N + N / 2);  // the normal
  nodes.push_back((N / 2) * N + 1);      // near the rim
  while (nodes.size() < 40) {
    std::size_t k = pick(rng);
    if (kirchhoff_node_q(N, k % N, k / N, lq).z() > 0) nodes.push_back(k);
  }
  auto direct = kirchhoff_nodes_direct(p, lq, N, nodes, KirchhoffIntegration::Exact);
  KirchhoffFastInfo info;
  auto fast = kirchhoff_table_fast(p, lq, N, 1e-10, &info, true, KirchhoffIntegration::Exact);
  double dmax = 0, num_d = 0, num_f = 0, den = 0;
  std::vector<double> ref(nodes.size());
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    ref[k] = brute_force_dk(s, kirchhoff_node_q(N, nodes[k] % N, nodes[k] / N, lq));
    dmax = std::max(dmax, ref[k]);
  }
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    EXPECT_LT(std::fabs(direct[k] - ref[k]), 1e-6 * ref[k] + 1e-12 * dmax) << "node " << nodes[k];
    EXPECT_LT(std::fabs(fast[nodes[k]] - ref[k]), 1e-6 * dmax) << "node " << nodes[k];
    num_d += std::fabs(direct[k] - ref[k]);
    num_f += std::fabs(fast[nodes[k]] - ref[k]);
    den += ref[k];
  }
  std::printf(
      "exact vs brute force on %zu nodes: direct %.3g, fast (chirp-z) %.3g relative L1; "
      "%zu-point rule, phase span %.3g\n",
      nodes.size(), num_d / den, num_f / den, info.points_per_triangle, info.phase_span);
  EXPECT_LT(num_d / den, 1e-6);
  EXPECT_LT(num_f / den, 1e-6);
  // The midpoint rule is a different (approximate) integral of the same surface.
  auto mid = kirchhoff_nodes_direct(p, lq, N, nodes, KirchhoffIntegration::Midpoint);
  double num_m = 0;
  for (std::size_t k = 0; k < nodes.size(); ++k) num_m += std::fabs(mid[k] - ref[k]);
  std::printf("midpoint rule vs brute force: %.3g relative L1\n", num_m / den);
  EXPECT_GT(num_m / den, 1e-3);
}

TEST(kirchhoff_exact, FlatMirrorAtNormalIsQzSquaredTimesArea) {
  Surface s(20, 16, 0.11e-6, 0.13e-6);
  const KirchhoffPatch p = make_kirchhoff_patch(s);
  const double qm = 4 * M_PI / 555e-9, a = 19 * 15 * 0.11e-6 * 0.13e-6;
  EXPECT_NEAR(p.area_w2_tri, a, 1e-12 * a);
  EXPECT_NEAR(kirchhoff_dk_direct(p, {0, 0, qm}, KirchhoffIntegration::Exact),
              qm * qm * a / (4 * M_PI * M_PI), 1e-10 * qm * qm * a);
}

// The fast exact table against the exact direct sums at the default accuracy (NUFFT, rule from
// the accuracy) on a brushed patch.
TEST(kirchhoff_exact, FastExactMatchesDirectExactAtDefaultAccuracy) {
  BrushedParams b = brushed_preset("stainless4");
  b.nx = 96;
  b.ny = 72;
  Surface s = generate_brushed(b);
  const KirchhoffPatch p = make_kirchhoff_patch(s);
  const double lq = 555e-9;
  const std::size_t N = 129;
  KirchhoffFastInfo info;
  auto fast = kirchhoff_table_fast(p, lq, N, KirchhoffOptions{}.accuracy, &info, false,
                                   KirchhoffIntegration::Exact);
  std::vector<std::size_t> nodes;
  std::mt19937_64 rng(9);
  std::uniform_int_distribution<std::size_t> pick(0, N * N - 1);
  while (nodes.size() < 150) {
    std::size_t k = pick(rng);
    if (kirchhoff_node_q(N, k % N, k / N, lq).z() > 0) nodes.push_back(k);
  }
  auto direct = kirchhoff_nodes_direct(p, lq, N, nodes, KirchhoffIntegration::Exact);
  double num = 0, den = 0;
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    num += std::fabs(fast[nodes[k]] - direct[k]);
    den += direct[k];
  }
  std::printf("stainless4 96x72 -> 129^2, exact: %zu terms, %zu-point rule, relative L1 %.3g\n",
              info.terms, info.points_per_triangle, num / den);
  EXPECT_LT(num / den, 1e-4);
}

namespace {

double raw_integral(const Surface& s, std::size_t n, KirchhoffIntegration m, std::size_t ss) {
  KirchhoffOptions o;
  o.resolution = n;
  o.integration = m;
  o.supersample = ss;
  KirchhoffAccumulator acc(o);
  acc.add(s);
  return acc.raw_integral();
}

}  // namespace

// Point samples of a D_K whose speckle is finer than the table's nodes do not integrate to 1
// (the table is then coarser than lambda_q / (2 L)); averages over sub-nodes do.
TEST(kirchhoff_exact, CellAveragesIntegrateToOneWherePointSamplesDoNot) {
  BrushedParams b = brushed_preset("stainless4");
  b.nx = 640;
  b.ny = 480;
  Surface s = generate_brushed(b);
  EXPECT_EQ(kirchhoff_auto_supersample(257, 555e-9, 640 * 0.11e-6, 480 * 0.11e-6), 3u);
  EXPECT_EQ(kirchhoff_auto_supersample(513, 555e-9, 640 * 0.11e-6, 480 * 0.11e-6), 1u);
  const double point = raw_integral(s, 257, KirchhoffIntegration::Midpoint, 1);
  const double cell = raw_integral(s, 257, KirchhoffIntegration::Midpoint, 0);
  std::printf(
      "stainless4 640x480 at N = 257 (midpoint rule): point samples %.4f, 3 x 3 cell "
      "averages %.4f\n",
      point, cell);
  EXPECT_GT(std::fabs(point - 1), 0.05);
  EXPECT_NEAR(cell, 1.0, 0.01);
}

// Acceptance: the exact-triangle D_K of one stainless #4 tile integrates to 1 within 1 % before
// normalising at N = 257, 513 and 1025 (automatic sub-node averaging).
TEST(kirchhoff_exact, SlowRawIntegralOfStainlessTileIsOne) {
  BrushedParams b = brushed_preset("stainless4");
  b.nx = 640;
  b.ny = 480;
  Surface s = generate_brushed(b);
  for (std::size_t n : {257u, 513u, 1025u}) {
    const double raw = raw_integral(s, n, KirchhoffIntegration::Exact, 0);
    std::printf("stainless4 640x480, exact, N = %zu: raw integral %.5f\n", n, raw);
    EXPECT_NEAR(raw, 1.0, 0.01) << n;
  }
}
