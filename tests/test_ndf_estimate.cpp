// Geometric NDF estimators against analytic expectations (issue 3 acceptance 1-4).
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <complex>
#include <random>

#include "core/fft.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/generate.hpp"
#include "microbrdf/ndf_estimate.hpp"

using namespace microbrdf;

namespace {

Surface gaussian(std::size_t n, double sigma, double tau_x, double tau_y, std::uint64_t seed = 1,
                 double angle = 0) {
  GaussianSurfaceParams p;
  p.nx = p.ny = n;
  p.sigma = sigma;
  p.tau_x = tau_x;
  p.tau_y = tau_y;
  p.seed = seed;
  p.angle = angle;
  return generate_gaussian(p);
}

NdfEstimateOptions opts(NdfMethod m, double sigma_f = 1e-6, std::size_t res = 1025) {
  NdfEstimateOptions o;
  o.method = m;
  o.filter_sigma_m = sigma_f;
  o.resolution = res;
  return o;
}

// Slopes of the Gaussian-smoothed surface g_s * z by FFT: d/dx <-> i k_x exp(-k^2 s^2 / 2).
void smoothed_slopes(const Surface& z, double s, std::vector<double>& gx, std::vector<double>& gy) {
  auto spec = detail::fft2_r2c(z.nx, z.ny, z.z);
  auto sy = spec;
  const std::size_t hx = z.nx / 2 + 1;
  for (std::size_t iy = 0; iy < z.ny; ++iy)
    for (std::size_t ix = 0; ix < hx; ++ix) {
      double kx = detail::fft_freq(ix, z.nx) / z.dx, ky = detail::fft_freq(iy, z.ny) / z.dy;
      double g = std::exp(-(kx * kx + ky * ky) * s * s / 2) / static_cast<double>(z.size());
      spec[iy * hx + ix] *= std::complex<double>(0, kx * g);
      sy[iy * hx + ix] *= std::complex<double>(0, ky * g);
    }
  gx = detail::fft2_c2r(z.nx, z.ny, std::move(spec));
  gy = detail::fft2_c2r(z.nx, z.ny, std::move(sy));
}

}  // namespace

// Acceptance 1: the naive NDF of a Gaussian surface is Beckmann with alpha = 2 sigma / tau per
// axis: rms slopes (= alpha / sqrt 2) within 3%, isotropic and anisotropic.
TEST(ndf_estimate, NaiveMatchesBeckmannMoments) {
  const double dx = 110e-9;
  for (auto [tx, ty] : {std::pair{20.0, 20.0}, std::pair{30.0, 12.0}}) {
    Surface s = gaussian(512, 0.1e-6, tx * dx, ty * dx, 3);
    auto ndf = estimate_ndf(s, opts(NdfMethod::Naive));
    // Forward differences over one triangle edge read 2 sigma^2 (1 - exp(-d^2/tau^2)) / d^2.
    for (auto [phi, tau] : {std::pair{0.0, tx * dx}, std::pair{M_PI / 2, ty * dx}}) {
      double alpha = 2 * 0.1e-6 / tau;
      EXPECT_NEAR(ndf.rms_slope(phi) / (alpha / std::sqrt(2.0)), 1.0, 0.03)
          << tx << " " << ty << " " << phi;
    }
    EXPECT_NEAR(ndf.integral(), 1.0, 1e-12);
    EXPECT_GT(ndf.mean_normal().z(), 1 - 1e-4);
    EXPECT_EQ(ndf.meta.samples_used, 2u * 511u * 511u);
  }
}

// Acceptance 2: on a full grid the filtered normals are the normals of the Gaussian-smoothed
// surface, and the rms slope follows alpha tau^2 / (tau^2 + 4 s^2) (docs/theory.md §3.4).
TEST(ndf_estimate, FilteredEqualsSmoothedSurfaceSlopes) {
  Surface s = gaussian(256, 0.1e-6, 3e-6, 1.5e-6, 5);
  const double sf = 0.5e-6;
  auto f = filtered_normals(s, sf, 6.0, 0.5);
  std::vector<double> gx, gy;
  smoothed_slopes(s, sf, gx, gy);
  const std::size_t border = 30;  // > 6 sigma_f / dx: away from the non-periodic edges
  double worst = 0;
  for (std::size_t iy = border; iy < s.ny - border; ++iy)
    for (std::size_t ix = border; ix < s.nx - border; ++ix) {
      std::size_t i = iy * s.nx + ix;
      double bx = -f.mx[i] / f.mz[i], by = -f.my[i] / f.mz[i];
      worst = std::max({worst, std::fabs(bx - gx[i]), std::fabs(by - gy[i])});
    }
  EXPECT_LT(worst, 1e-4 * 0.1);  // rms slope ~0.07: agreement to ~1e-4 relative
}

// The filtered spectrum peaks near k ~ 1/sqrt(s^2 + tau^2/4): a field of only a few such
// wavelengths samples it coarsely (the discrete k-sum differs from the continuum integral by
// ~6% at s = tau = 2 um on a 56 um field). A 256 um field (1024 samples at 0.25 um) brings the
// worst case to ~3%: 0.06%, 0.2%, 0.7%, 3.4% for s = 0.25, 0.5, 1, 2 um.
TEST(ndf_estimate, FilteredRmsSlopeFollowsTheory) {
  const double sigma = 0.1e-6, tau = 2e-6;
  GaussianSurfaceParams p;
  p.nx = p.ny = 1024;
  p.dx = p.dy = 0.25e-6;
  p.sigma = sigma;
  p.tau_x = p.tau_y = tau;
  p.seed = 7;
  Surface s = generate_gaussian(p);
  for (double sf : {0.25e-6, 0.5e-6, 1e-6, 2e-6}) {
    auto ndf = estimate_ndf(s, opts(NdfMethod::Filtered, sf, 513));
    double alpha = 2 * sigma / tau;
    double expect = alpha * tau * tau / (tau * tau + 4 * sf * sf) / std::sqrt(2.0);
    EXPECT_NEAR(ndf.rms_slope(0) / expect, 1.0, 0.05) << sf;
    EXPECT_NEAR(ndf.rms_slope(M_PI / 2) / expect, 1.0, 0.05) << sf;
  }
}

// Acceptance 3: normalisation at several resolutions; tilted plane; sigma_f -> 0; holes.
TEST(ndf_estimate, NormalisedAtEveryResolution) {
  Surface s = gaussian(256, 0.1e-6, 2e-6, 2e-6, 2);
  for (std::size_t n : {257u, 513u, 1025u})
    for (auto m : {NdfMethod::Naive, NdfMethod::Filtered}) {
      auto ndf = estimate_ndf(s, opts(m, 0.5e-6, n));
      EXPECT_NEAR(ndf.integral(), 1.0, 1e-3) << n;
      EXPECT_EQ(ndf.resolution(), n);
    }
}

TEST(ndf_estimate, TiltedPlaneGivesOnePeakAtItsNormal) {
  Surface s(200, 150, 0.1e-6, 0.1e-6);
  const double gx = 0.2, gy = -0.1;  // dz/dx, dz/dy
  for (std::size_t iy = 0; iy < s.ny; ++iy)
    for (std::size_t ix = 0; ix < s.nx; ++ix)
      s.at(ix, iy) = gx * static_cast<double>(ix) * s.dx + gy * static_cast<double>(iy) * s.dy;
  Eigen::Vector3d n(-gx, -gy, 1);
  n.normalize();
  for (auto m : {NdfMethod::Naive, NdfMethod::Filtered}) {
    auto ndf = estimate_ndf(s, opts(m, 0.3e-6, 1025));
    EXPECT_LT((ndf.peak() - n).norm(), ndf.spacing()) << static_cast<int>(m);
    // Bilinear splatting is exact for (m_x, m_y); m_z of the node mix is off by O(Delta^2).
    EXPECT_LT((ndf.mean_normal() - n).norm(), ndf.spacing() * ndf.spacing()) << static_cast<int>(m);
    // All the mass sits on the four nodes around the normal.
    std::size_t nonzero = 0;
    for (double v : ndf.values()) nonzero += v > 0;
    EXPECT_LE(nonzero, 4u);
  }
}

TEST(ndf_estimate, FilteredApproachesNaiveAsSigmaShrinks) {
  const double dx = 110e-9;
  Surface s = gaussian(512, 0.1e-6, 20 * dx, 20 * dx, 9);
  double naive = estimate_ndf(s, opts(NdfMethod::Naive)).rms_slope(0);
  double prev_err = 1e9;
  for (double k : {4.0, 2.0, 1.0, 0.6}) {
    double filt = estimate_ndf(s, opts(NdfMethod::Filtered, k * dx)).rms_slope(0);
    double err = std::fabs(filt / naive - 1);
    EXPECT_LT(err, prev_err) << k;
    prev_err = err;
  }
  EXPECT_LT(prev_err, 0.03);
}

TEST(ndf_estimate, HolesBarelyChangeFilteredSlopesAndMatchBruteForce) {
  Surface s = gaussian(384, 0.1e-6, 2e-6, 1e-6, 4);
  const double sf = 0.5e-6;
  auto full = estimate_ndf(s, opts(NdfMethod::Filtered, sf));
  Surface random_holes = s, big_holes = s;
  std::mt19937 rng(1);
  for (std::size_t i = 0; i < s.size(); ++i)
    if (rng() % 20 == 0) random_holes.invalidate(i);  // 5%
  for (auto [cx, cy, r] :
       {std::tuple{100, 100, 12}, std::tuple{250, 300, 20}, std::tuple{300, 60, 8}})
    for (int y = cy - r; y <= cy + r; ++y)
      for (int x = cx - r; x <= cx + r; ++x)
        if ((x - cx) * (x - cx) + (y - cy) * (y - cy) <= r * r)
          big_holes.invalidate(static_cast<std::size_t>(y) * s.nx + static_cast<std::size_t>(x));
  for (const Surface* h : {&random_holes, &big_holes}) {
    auto ndf = estimate_ndf(*h, opts(NdfMethod::Filtered, sf));
    EXPECT_NEAR(ndf.rms_slope(0) / full.rms_slope(0), 1.0, 0.01);
    EXPECT_NEAR(ndf.rms_slope(M_PI / 2) / full.rms_slope(M_PI / 2), 1.0, 0.01);
    EXPECT_GT(ndf.meta.samples_skipped + ndf.meta.samples_used, 0u);
    // Normals next to holes (and everywhere on a sparse grid) equal the direct weighted fit.
    auto f = filtered_normals(*h, sf, 4.0, 0.5);
    int checked = 0;
    for (std::size_t iy = 0; iy < h->ny; iy += 7)
      for (std::size_t ix = 0; ix < h->nx; ix += 5) {
        std::size_t i = iy * h->nx + ix;
        double ref[3];
        bool ok = filtered_normal_direct(*h, ix, iy, sf, 4.0, 0.5, ref);
        ASSERT_EQ(ok, f.mz[i] > 0) << ix << "," << iy;
        if (!ok) continue;
        EXPECT_NEAR(f.mx[i], ref[0], 1e-9);
        EXPECT_NEAR(f.my[i], ref[1], 1e-9);
        EXPECT_NEAR(f.mz[i], ref[2], 1e-9);
        ++checked;
      }
    EXPECT_GT(checked, 3000);
  }
}

TEST(ndf_estimate, ScanSetAveragesByProjectedArea) {
  // Two tilted planes of different areas: the NDF holds two peaks with mass ratio = area ratio.
  auto plane = [](std::size_t nx, std::size_t ny, double g) {
    Surface s(nx, ny, 0.1e-6, 0.1e-6);
    for (std::size_t iy = 0; iy < ny; ++iy)
      for (std::size_t ix = 0; ix < nx; ++ix) s.at(ix, iy) = g * static_cast<double>(ix) * s.dx;
    return s;
  };
  NdfAccumulator acc(opts(NdfMethod::Naive, 1e-6, 257));
  acc.add(plane(101, 101, 0.3));   // 100 x 100 cells
  acc.add(plane(201, 101, -0.3));  // 200 x 100 cells
  auto ndf = acc.result();
  double left = 0, right = 0;
  for (std::size_t iy = 0; iy < 257; ++iy)
    for (std::size_t ix = 0; ix < 257; ++ix) (ndf.node_x(ix) < 0 ? left : right) += ndf.at(ix, iy);
  EXPECT_NEAR(right / left, 2.0, 1e-9);  // dz/dx < 0 tilts the normal to +x
}

// The streaming pass cuts the scan into column blocks per thread: normals and tables must be
// the same bit for bit whatever the thread count (odd sizes, holes, blocks of unequal width).
TEST(ndf_estimate, FilteredIdenticalForAnyThreadCount) {
  Surface s = gaussian(203, 0.1e-6, 1e-6, 0.6e-6, 11);
  std::mt19937 rng(5);
  for (std::size_t i = 0; i < s.size(); ++i)
    if (rng() % 9 == 0) s.invalidate(i);
  const int before = omp_get_max_threads();
  omp_set_num_threads(1);
  const NormalField f1 = filtered_normals(s, 0.4e-6, 4.0, 0.5);
  const TabulatedNdf t1 = estimate_ndf(s, opts(NdfMethod::Filtered, 0.4e-6, 257));
  EXPECT_GT(f1.used, s.size() / 2);
  for (int th : {2, 3, 5}) {
    omp_set_num_threads(th);
    const NormalField f = filtered_normals(s, 0.4e-6, 4.0, 0.5);
    const TabulatedNdf t = estimate_ndf(s, opts(NdfMethod::Filtered, 0.4e-6, 257));
    EXPECT_EQ(f.used, f1.used);
    EXPECT_EQ(f.skipped, f1.skipped);
    EXPECT_TRUE(f.mx == f1.mx && f.my == f1.my && f.mz == f1.mz) << th;
    EXPECT_TRUE(t.values() == t1.values()) << th;
  }
  omp_set_num_threads(before);
}

// Large enough for the splat to run on several threads (each owns a band of table rows): the
// naive and filtered tables are the same bit for bit for any thread count, and the naive table
// equals a plain bilinear splat of the triangles' normals written here (whole-disk window, nodes
// at -1 + 2 k / (N - 1)), up to the normalisation.
TEST(ndf_estimate, SplatOnSeveralThreadsMatchesPlainLoop) {
  GaussianSurfaceParams gp;
  gp.nx = 400;
  gp.ny = 300;
  gp.tau_x = 1e-6;
  gp.tau_y = 0.5e-6;
  gp.seed = 12;
  Surface s = generate_gaussian(gp);
  std::mt19937 rng(8);
  for (std::size_t i = 0; i < s.size(); ++i)
    if (rng() % 11 == 0) s.invalidate(i);
  const std::size_t n = 257;
  std::vector<double> ref(n * n, 0.0);
  const double h = 2.0 / static_cast<double>(n - 1);
  auto splat = [&](double gx, double gy) {
    const double norm = std::sqrt(1 + gx * gx + gy * gy);
    const double fx = (-gx / norm + 1) / h, fy = (-gy / norm + 1) / h;
    const auto ix = static_cast<std::size_t>(fx), iy = static_cast<std::size_t>(fy);
    const double tx = fx - static_cast<double>(ix), ty = fy - static_cast<double>(iy);
    ref[iy * n + ix] += (1 - tx) * (1 - ty);
    ref[iy * n + ix + 1] += tx * (1 - ty);
    ref[(iy + 1) * n + ix] += (1 - tx) * ty;
    ref[(iy + 1) * n + ix + 1] += tx * ty;
  };
  for (std::size_t y = 0; y + 1 < s.ny; ++y)
    for (std::size_t x = 0; x + 1 < s.nx; ++x) {
      auto z = [&](std::size_t a, std::size_t b) { return s.z[b * s.nx + a]; };
      auto ok = [&](std::size_t a, std::size_t b) { return s.valid[b * s.nx + a] != 0; };
      if (ok(x, y) && ok(x + 1, y) && ok(x + 1, y + 1))
        splat((z(x + 1, y) - z(x, y)) / s.dx, (z(x + 1, y + 1) - z(x + 1, y)) / s.dy);
      if (ok(x, y) && ok(x + 1, y + 1) && ok(x, y + 1))
        splat((z(x + 1, y + 1) - z(x, y + 1)) / s.dx, (z(x, y + 1) - z(x, y)) / s.dy);
    }
  const int before = omp_get_max_threads();
  omp_set_num_threads(1);
  const TabulatedNdf naive1 = estimate_ndf(s, opts(NdfMethod::Naive, 0, n));
  const TabulatedNdf filtered1 = estimate_ndf(s, opts(NdfMethod::Filtered, 0.3e-6, n));
  double sum_ref = 0, sum_t = 0;
  for (std::size_t i = 0; i < n * n; ++i) {
    const double x = -1 + h * static_cast<double>(i % n), y = -1 + h * static_cast<double>(i / n);
    const double r = x * x + y * y <= 1 ? ref[i] : 0.0;  // nodes outside the unit disk are cleared
    sum_ref += r;
    sum_t += naive1.values()[i];
    ref[i] = r;
  }
  double worst = 0;
  for (std::size_t i = 0; i < n * n; ++i)
    worst = std::max(worst, std::abs(naive1.values()[i] / sum_t - ref[i] / sum_ref));
  EXPECT_LT(worst, 1e-15);
  for (int th : {2, 3, 5}) {
    omp_set_num_threads(th);
    EXPECT_TRUE(estimate_ndf(s, opts(NdfMethod::Naive, 0, n)).values() == naive1.values()) << th;
    EXPECT_TRUE(estimate_ndf(s, opts(NdfMethod::Filtered, 0.3e-6, n)).values() ==
                filtered1.values())
        << th;
  }
  omp_set_num_threads(before);
}

// A smooth surface (rms slope ~0.0014, like a polished flat) at N = 129: the whole-disk table
// (node spacing 0.0156) holds the lobe on about one node, and the bilinear splat alone inflates
// its rms slope several-fold; a zoomed window (half-width 12 rms slopes) resolves it and gives
// the surface's own rms slope within 1%, normalised over the window, with the share of the
// normals inside the window recorded. Splats are the same bilinear rule on the finer grid, so
// a window holding every normal has window_mass 1.
TEST(ndf_estimate, ZoomedWindowResolvesASmoothSurface) {
  const Surface s = gaussian(256, 2e-9, 2e-6, 2e-6);  // alpha = 2 sigma / tau = 0.002
  double sx = 0;
  std::size_t count = 0;
  for (std::size_t iy = 0; iy + 1 < s.ny; ++iy)
    for (std::size_t ix = 0; ix + 1 < s.nx; ++ix) {
      // The naive estimator's lower-triangle slope along x.
      const double g = (s.z[iy * s.nx + ix + 1] - s.z[iy * s.nx + ix]) / s.dx;
      sx += g * g;
      ++count;
    }
  const double rms_x = std::sqrt(sx / static_cast<double>(count));
  NdfEstimateOptions o = opts(NdfMethod::Naive, 1e-6, 129);
  const TabulatedNdf coarse = estimate_ndf(s, o);
  o.window = zoom_window(0, 0, 12 * rms_x);
  const TabulatedNdf zoom = estimate_ndf(s, o);
  EXPECT_EQ(zoom.window(), o.window);
  EXPECT_EQ(zoom.meta.sampling, "cell");
  EXPECT_EQ(coarse.meta.sampling, "cell");
  EXPECT_NEAR(zoom.integral(), 1.0, 1e-12);
  EXPECT_GT(zoom.meta.window_mass, 0.999);
  EXPECT_LE(zoom.meta.window_mass, 1.0);
  EXPECT_EQ(coarse.meta.window_mass, 1.0);
  const double zr = zoom.rms_slope(0), cr = coarse.rms_slope(0);
  std::printf("smooth surface rms slope x %.5g: whole-disk table %.5g, zoomed %.5g\n", rms_x, cr,
              zr);
  EXPECT_NEAR(zr / rms_x, 1.0, 0.01);
  EXPECT_GT(cr / rms_x, 2.0);
  // A window that cuts the lobe keeps a share < 1 and renormalises what is inside.
  o.window = zoom_window(2 * rms_x, 0, rms_x);
  const TabulatedNdf part = estimate_ndf(s, o);
  EXPECT_LT(part.meta.window_mass, 0.5);
  EXPECT_NEAR(part.integral(), 1.0, 1e-12);
  // Nothing in the window: an error that says so.
  o.window = zoom_window(0.5, 0.5, 0.01);
  EXPECT_THROW(estimate_ndf(s, o), InputError);
  // Filtered normals splat onto the window the same way.
  o = opts(NdfMethod::Filtered, 2e-6, 129);
  o.window = zoom_window(0, 0, 12 * rms_x);
  const TabulatedNdf fz = estimate_ndf(s, o);
  EXPECT_NEAR(fz.integral(), 1.0, 1e-12);
  EXPECT_GT(fz.meta.window_mass, 0.999);
}
