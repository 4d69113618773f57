// Kirchhoff distribution D_K against physics (issue 5 acceptance 1-3): grating orders and the
// Bessel expansion, the rough (Beckmann / geometric) and smooth (coherent fraction) limits;
// scan averaging and the Kirchhoff BRDF.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "microbrdf/brdf_albedo.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/generate.hpp"
#include "microbrdf/kirchhoff.hpp"
#include "microbrdf/kirchhoff_brdf.hpp"
#include "microbrdf/ndf_estimate.hpp"
#include "surface_test_util.hpp"

using namespace microbrdf;

namespace {

constexpr double kLq = 555e-9;

TabulatedNdf table(const std::vector<double>& v, std::size_t n) {
  TabulatedNdf t(n);
  t.values() = v;
  return t;
}

}  // namespace

// Acceptance 1. z = A sin(2 pi x / P): exp(-i q_z A sin(K x)) = sum_n J_n(q_z A) exp(-i n K x),
// so order n sits at h_x = n lambda_q / (2P) (up to sign) and, with q.m integrated by parts on
// the periodic profile, carries D_K mass (|q| / q_z,n)^2 J_n(q_z,n A)^2 (obliquity factor
// 1/cos^2 theta_h), q_z,n = |q| sqrt(1 - h_x,n^2).
TEST(kirchhoff, GratingOrdersFollowBesselWithObliquity) {
  GratingParams g;
  g.nx = 640;
  g.ny = 48;
  g.period = 5e-6;
  g.amplitude = 0.08e-6;
  Surface s = generate_grating(g);
  const std::size_t N = 1025;
  auto p = make_kirchhoff_patch(s, KirchhoffWindow::Hann);
  auto t = table(kirchhoff_table_fast(p, kLq, N), N);
  const double qm = 4 * M_PI / kLq, spacing = kLq / (2 * g.period), d = t.spacing();
  const int nmax = static_cast<int>(1 / spacing);
  std::vector<double> meas, pred;
  double msum = 0, psum = 0;
  for (int n = -nmax; n <= nmax; ++n) {
    double hx = n * spacing, mass = 0;
    for (std::size_t iy = 0; iy < N; ++iy)
      for (std::size_t ix = 0; ix < N; ++ix)
        if (std::fabs(t.node_x(ix) - hx) < 0.5 * spacing) mass += t.at(ix, iy) * d * d;
    double cz = std::sqrt(std::max(0.0, 1 - hx * hx));
    double jn = cz > 0 ? std::cyl_bessel_j(std::abs(n), qm * cz * g.amplitude) : 0;
    meas.push_back(mass);
    pred.push_back(cz > 0 ? jn * jn / (cz * cz) : 0);
    msum += mass;
    psum += pred.back();
  }
  int checked = 0;
  for (int n = -nmax; n <= nmax; ++n) {
    double fm = meas[static_cast<std::size_t>(n + nmax)] / msum;
    double fp = pred[static_cast<std::size_t>(n + nmax)] / psum;
    if (fp < 0.01) continue;
    ++checked;
    std::printf("order %+d: measured %.5f predicted %.5f (rel %.2e)\n", n, fm, fp, fm / fp - 1);
    EXPECT_NEAR(fm / fp, 1.0, 0.02) << "order " << n;
  }
  EXPECT_GE(checked, 5);
  // Peak positions: the largest node of order 1 lies within one node of lambda_q / (2P).
  double best = 0, where = 0;
  for (std::size_t ix = 0; ix < N; ++ix)
    if (std::fabs(t.node_x(ix) - spacing) < 0.5 * spacing && t.at(ix, N / 2) > best) {
      best = t.at(ix, N / 2);
      where = t.node_x(ix);
    }
  EXPECT_NEAR(where, spacing, d);
  std::printf("sum of D_K over the disk before normalising: %.4f\n", t.integral());
}

// Acceptance 2. sigma >> lambda: D_K -> Beckmann alpha = 2 sigma / tau, and the naive geometric
// NDF of the same surface; compared by their slope moments.
TEST(kirchhoff, RoughGaussianApproachesBeckmannAndGeometric) {
  const double sigma = 1e-6, tau = 5e-6;
  Surface s = test_util::isotropic_gaussian(512, 0.11e-6, sigma, tau, 3);
  KirchhoffOptions o;
  o.resolution = 257;
  o.patch_x = o.patch_y = 0;  // one patch
  o.window = KirchhoffWindow::Hann;
  // The rough limit holds for either integration; the midpoint rule keeps this test short (45
  // terms; the exact rule needs ~40 points per triangle at these slopes).
  o.integration = KirchhoffIntegration::Midpoint;
  KirchhoffAccumulator acc(o);
  acc.add(s);
  TabulatedNdf dk = acc.result();
  NdfEstimateOptions no;
  no.method = NdfMethod::Naive;
  no.resolution = 257;
  TabulatedNdf geo = estimate_ndf(s, no);
  const double alpha = 2 * sigma / tau;
  for (double phi : {0.0, M_PI / 2}) {
    double k = dk.rms_slope(phi), gm = geo.rms_slope(phi), b = alpha / std::sqrt(2.0);
    std::printf("phi %.2f: rms slope D_K %.4f, naive geometric %.4f, Beckmann %.4f (%zu terms)\n",
                phi, k, gm, b, acc.last_info().terms);
    EXPECT_NEAR(k / b, 1.0, 0.05);
    EXPECT_NEAR(k / gm, 1.0, 0.05);
  }
  std::printf("raw integral %.4f\n", acc.raw_integral());
  EXPECT_NEAR(acc.raw_integral(), 1.0, 0.1);
}

// Acceptance 3. sigma << lambda: the specular (coherent) peak holds exp(-(q_z sigma)^2) of the
// total.
TEST(kirchhoff, SmoothGaussianSpecularFractionIsDebyeWaller) {
  for (double sigma : {0.01e-6, 0.02e-6, 0.035e-6}) {
    Surface s = test_util::isotropic_gaussian(512, 0.11e-6, sigma, 1e-6, 5);
    const std::size_t N = 1025;
    auto p = make_kirchhoff_patch(s, KirchhoffWindow::Hann);
    auto t = table(kirchhoff_table_fast(p, kLq, N), N);
    const double d = t.spacing(), c = 0.5 * (N - 1);
    // Peak: r < 8 nodes (Hann main lobe +-5 nodes here); the diffuse halo under it is the mean
    // of the annulus 10..20 nodes.
    double peak = 0, ann = 0, total = 0;
    std::size_t npk = 0, nann = 0;
    for (std::size_t iy = 0; iy < N; ++iy)
      for (std::size_t ix = 0; ix < N; ++ix) {
        double r = std::hypot(ix - c, iy - c), v = t.at(ix, iy);
        total += v;
        if (r < 8) {
          peak += v;
          ++npk;
        } else if (r >= 10 && r < 20) {
          ann += v;
          ++nann;
        }
      }
    double frac = (peak - ann / nann * npk) / total;
    double qz = 4 * M_PI / kLq, expect = std::exp(-qz * qz * sigma * sigma);
    std::printf("sigma %.0f nm: specular fraction %.4f, exp(-g) %.4f, integral %.4f\n", sigma * 1e9,
                frac, expect, total * d * d);
    EXPECT_NEAR(frac / expect, 1.0, 0.05);
  }
}

TEST(kirchhoff, ScanSetAveragesPatchesByArea) {
  BrushedParams b = brushed_preset("stainless4");
  b.nx = 256;
  b.ny = 128;
  Surface s = generate_brushed(b);
  KirchhoffOptions o;
  o.resolution = 129;
  o.patch_x = 14e-6;  // 256 * 0.11 / 14 = 2.01 -> 2 tiles of 128
  o.patch_y = 0;
  o.window = KirchhoffWindow::None;  // as the hand-made patches below
  KirchhoffAccumulator acc(o);
  acc.add(s);
  EXPECT_EQ(acc.patches(), 2u);
  TabulatedNdf avg = acc.result();
  EXPECT_EQ(avg.meta.method, "kirchhoff");
  EXPECT_DOUBLE_EQ(avg.meta.wavelength_m, kLq);
  EXPECT_NEAR(avg.integral(), 1.0, 1e-12);
  // Same as averaging the two halves by hand.
  auto a = make_kirchhoff_patch(s, 0, 0, 128, 128), c = make_kirchhoff_patch(s, 128, 0, 128, 128);
  auto ta = kirchhoff_table_fast(a, kLq, 129, o.accuracy, nullptr, false, o.integration),
       tc = kirchhoff_table_fast(c, kLq, 129, o.accuracy, nullptr, false, o.integration);
  const double wa = kirchhoff_area_w2(a, o.integration), wc = kirchhoff_area_w2(c, o.integration);
  TabulatedNdf ref(129);
  for (std::size_t i = 0; i < ta.size(); ++i) ref.values()[i] = wa * ta[i] + wc * tc[i];
  ref.normalise();
  double diff = 0;
  for (std::size_t i = 0; i < ta.size(); ++i) diff += std::fabs(ref.values()[i] - avg.values()[i]);
  EXPECT_LT(diff * avg.spacing() * avg.spacing(), 1e-12);
  // --direct gives the same table.
  o.direct = true;
  o.resolution = 33;
  o.patch_x = o.patch_y = 0;
  Surface small = s;
  KirchhoffAccumulator dacc(o), facc([&] {
    auto f = o;
    f.direct = false;
    return f;
  }());
  GaussianSurfaceParams gp;
  gp.nx = 40;
  gp.ny = 30;
  gp.sigma = 0.1e-6;
  Surface g = generate_gaussian(gp);
  dacc.add(g);
  facc.add(g);
  auto dt = dacc.result(), ft = facc.result();
  double l1 = 0;
  for (std::size_t i = 0; i < dt.values().size(); ++i)
    l1 += std::fabs(dt.values()[i] - ft.values()[i]);
  EXPECT_LT(l1 * dt.spacing() * dt.spacing(), 1e-4);
}

TEST(kirchhoff, BrdfIsEq8AndSamplesConsistently) {
  GaussianSurfaceParams gp;
  gp.nx = gp.ny = 256;
  gp.sigma = 0.3e-6;
  gp.tau_x = gp.tau_y = 3e-6;
  Surface s = generate_gaussian(gp);
  KirchhoffOptions o;
  o.resolution = 257;
  o.patch_x = o.patch_y = 0;
  o.integration = KirchhoffIntegration::Midpoint;  // eq. 8 does not depend on the integration
  TabulatedNdf t = estimate_kirchhoff(s, o);
  auto fres = std::make_shared<ConductorFresnel>(metal("Al"));
  KirchhoffBrdf brdf({t}, fres);
  Vec3 wi(-std::sin(0.5), 0, std::cos(0.5));
  Vec3 wo(std::sin(0.6) * std::cos(0.1), std::sin(0.6) * std::sin(0.1), std::cos(0.6));
  Vec3 h = (wi + wo).normalized();
  double expect = t.eval(h) * fres->eval(wi.dot(h), 550e-9) / (4 * wi.z() * wo.z());
  EXPECT_NEAR(brdf.eval(wi, wo, 550e-9), expect, 1e-12 * expect);
  // Sampling: the estimator of the albedo agrees with quadrature.
  double a_quad = directional_albedo(brdf, wi, 550e-9, 128, 256);
  double a_samp = directional_albedo_sampled(brdf, wi, 550e-9, 256);
  EXPECT_NEAR(a_samp, a_quad, 0.02 * a_quad);
  // Spectral use: two tables, the BRDF interpolates log D_K linearly in log lambda_q (the
  // cubic through four tables reduces to this with two), the nearest table outside them.
  o.wavelength_q = 450e-9;
  TabulatedNdf t450 = estimate_kirchhoff(s, o);
  o.wavelength_q = 650e-9;
  TabulatedNdf t650 = estimate_kirchhoff(s, o);
  KirchhoffBrdf spectral({t650, t450}, fres);
  double lq = 2 * 550e-9 / (wi + wo).norm();
  ASSERT_GT(lq, 450e-9);
  ASSERT_LT(lq, 650e-9);
  double u = std::log(lq / 450e-9) / std::log(650e-9 / 450e-9);
  double dk = std::pow(t450.eval(h), 1 - u) * std::pow(t650.eval(h), u);
  EXPECT_NEAR(spectral.dk(h, lq), dk, 1e-12 * dk);
  EXPECT_DOUBLE_EQ(spectral.dk(h, 300e-9), t450.eval(h));
  EXPECT_DOUBLE_EQ(spectral.dk(h, 900e-9), t650.eval(h));
}

// The specular part as the mean field over tiles (KirchhoffOptions::separate_specular): on a
// smooth Gaussian surface its energy is exp(-g) and sits on one node; the diffuse part left
// around it follows the Beckmann-Spizzichino series (written here on its own), where the
// tiles' diffraction pattern of the specular peak would otherwise dominate.
TEST(kirchhoff, MeanFieldOverTilesIsTheSpecularPart) {
  GaussianSurfaceParams gp;
  gp.nx = gp.ny = 1024;
  gp.dx = 0.11e-6;
  gp.sigma = 10e-9;
  gp.tau_x = gp.tau_y = 1e-6;
  gp.seed = 11;
  Surface s = generate_gaussian(gp);
  KirchhoffOptions o;
  o.resolution = 257;
  o.patch_x = o.patch_y = 14e-6;  // 8 x 8 tiles of 128 samples
  KirchhoffAccumulator acc(o);
  acc.add(s);
  const TabulatedNdf t = acc.result();
  o.separate_specular = false;
  KirchhoffAccumulator plain_acc(o);
  plain_acc.add(s);
  const TabulatedNdf plain = plain_acc.result();
  EXPECT_NE(t.meta.notes.find("specular part (the mean field"), std::string::npos) << t.meta.notes;
  const std::size_t N = 257, c = N / 2;
  const double d = t.spacing(), qm = 4 * M_PI / kLq, g = qm * qm * gp.sigma * gp.sigma;
  // The specular node holds exp(-g) of the energy (each node's share is D Delta^2).
  const double spec = t.at(c, c) * d * d;
  std::printf("specular node %.4f of the energy, exp(-g) %.4f\n", spec, std::exp(-g));
  EXPECT_NEAR(spec / std::exp(-g), 1.0, 0.03);
  // Ring averages of the diffuse part against the series at |h_xy| = r.
  auto series = [&](double hxy) {
    const double hz = std::sqrt(1 - hxy * hxy), qxy = qm * hxy, qz = qm * hz;
    const double gz = qz * qz * gp.sigma * gp.sigma, tau = gp.tau_x;
    double sum = 0, term = std::exp(-gz);
    for (int m = 1; m < 40; ++m) {
      term *= gz / m;
      sum += term * (M_PI * tau * tau / m) * std::exp(-qxy * qxy * tau * tau / (4 * m));
    }
    return std::pow(qm, 4) / (4 * M_PI * M_PI * qz * qz) * sum;
  };
  // Near the peak, where the separation matters (further out both tables agree, and the
  // far lobe is checked against the series by tests/cli_slow/kirchhoff_defaults.sh).
  for (double r : {0.02, 0.035, 0.05}) {
    double sum = 0, sum_plain = 0;
    std::size_t n = 0;
    for (std::size_t iy = 0; iy < N; ++iy)
      for (std::size_t ix = 0; ix < N; ++ix) {
        const double mx = -1 + d * ix, my = -1 + d * iy;
        if (std::fabs(std::hypot(mx, my) - r) > d) continue;
        sum += t.at(ix, iy);
        sum_plain += plain.at(ix, iy);
        ++n;
      }
    const double ring = sum / n, ring_plain = sum_plain / n, ref = series(r);
    std::printf("|h_xy| %.2f: diffuse %.4g, without the separation %.4g, series %.4g (%zu nodes)\n",
                r, ring, ring_plain, ref, n);
    EXPECT_NEAR(ring / ref, 1.0, 0.06);
    if (r == 0.02) {
      EXPECT_GT(ring_plain / ref, 1.5);  // the tiles' diffraction of the peak
    }
  }
}
