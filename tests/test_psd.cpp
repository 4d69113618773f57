// The areal PSD of a scan (include/microbrdf/psd.hpp): normalisation, the analytic PSD of a
// generated Gaussian surface, symmetry, interpolation, tiles, invalid samples, memory budget.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <vector>

#include "microbrdf/error.hpp"
#include "microbrdf/memory_budget.hpp"
#include "microbrdf/psd.hpp"
#include "surface_test_util.hpp"

using namespace microbrdf;

namespace {

constexpr double kSigma = 5e-9, kTau = 5e-6, kDx = 0.25e-6;

// The PSD of C(r) = sigma^2 exp(-r^2 / tau^2) in cycles/m: the 2-D Fourier transform
// integral C(r) exp(-2 pi i f.r) d^2r = pi tau^2 sigma^2 exp(-pi^2 tau^2 f^2).
double gaussian_psd(double f) {
  return M_PI * kTau * kTau * kSigma * kSigma * std::exp(-M_PI * M_PI * kTau * kTau * f * f);
}

const Surface& gaussian_512() {
  static const Surface s = test_util::isotropic_gaussian(512, kDx, kSigma, kTau, 7);
  return s;
}

double sq_of(const Surface& s) {
  double m = 0, m2 = 0;
  const double n = static_cast<double>(s.valid_count());
  for (std::size_t i = 0; i < s.size(); ++i)
    if (s.valid[i]) m += s.z[i];
  m /= n;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (s.valid[i]) m2 += (s.z[i] - m) * (s.z[i] - m);
  return std::sqrt(m2 / n);
}

}  // namespace

TEST(psd, IntegralIsSqSquaredWithoutWindow) {
  // Parseval on the valid samples: a non-periodic surface with a hole, no window, one tile.
  Surface s = test_util::isotropic_gaussian(200, 150, kDx, kSigma, 1e-6, 3);
  for (std::size_t i = 0; i < s.size(); i += 7) s.z[i] += 2e-9 * std::sin(0.3 * i);
  for (std::size_t i = 4000; i < 4300; ++i) s.invalidate(i);
  const double sq = sq_of(s);
  PsdOptions o;
  o.window = PsdWindow::None;
  const AreaPsd p = areal_psd(s, o);
  EXPECT_NEAR(p.integral() / (sq * sq), 1.0, 1e-12);
  EXPECT_NEAR(p.sq, sq, 1e-15);
  EXPECT_EQ(p.at_node(p.nfx / 2, p.nfy / 2), 0.0);  // the zero-frequency bin
  EXPECT_EQ(p.tiles, 1u);
  EXPECT_DOUBLE_EQ(p.dfx, 1 / (200 * kDx));
  EXPECT_DOUBLE_EQ(p.dfy, 1 / (150 * kDx));
}

TEST(psd, WindowPlaysDownPowerAtTheEdges) {
  // A bowl (form a plane fit leaves) holds its power at the edges: the Hann estimate holds a
  // fraction of Sq^2, and says so (integral_over_sq2), instead of spreading it over all f.
  Surface s(256, 256, kDx, kDx);
  for (std::size_t iy = 0; iy < 256; ++iy)
    for (std::size_t ix = 0; ix < 256; ++ix) {
      const double u = (ix - 127.5) / 128, v = (iy - 127.5) / 128;
      s.at(ix, iy) = 10e-9 * (u * u + v * v);
    }
  const AreaPsd p = areal_psd(s);
  const double ratio = p.integral() / (p.sq * p.sq);
  EXPECT_LT(ratio, 0.5);
  EXPECT_NEAR(psd_json(p)["integral_over_sq2"].get<double>(), ratio, 1e-12);
}

TEST(psd, GeneratedGaussianMatchesItsAnalyticPsd) {
  // The generator gives every Fourier coefficient the target modulus: the periodogram (no
  // window) IS the analytic PSD at every node but the zero-frequency one, up to the generator's
  // renormalisation to rms sigma exactly (the missing zero-frequency power, pi tau^2 df^2 =
  // 0.5 %).
  PsdOptions o;
  o.window = PsdWindow::None;
  const AreaPsd p = areal_psd(gaussian_512(), o);
  const double peak = gaussian_psd(0);
  double worst = 0;
  int n = 0;
  for (std::size_t iy = 0; iy < p.nfy; ++iy)
    for (std::size_t ix = 0; ix < p.nfx; ++ix) {
      const double f = std::hypot(p.fx(ix), p.fy(iy));
      if (f == 0 || gaussian_psd(f) < 1e-6 * peak) continue;
      worst = std::max(worst, std::fabs(p.at_node(ix, iy) / gaussian_psd(f) - 1));
      ++n;
    }
  EXPECT_GT(n, 500);
  EXPECT_LT(worst, 0.01) << "nodes " << n;
  std::printf("generated Gaussian vs analytic PSD: %d nodes, worst %.3f %%\n", n, 100 * worst);
}

// The power within |f| < F: sigma^2 (1 - exp(-pi^2 tau^2 F^2)) for the analytic PSD.
double analytic_power_within(double f) {
  return kSigma * kSigma * (1 - std::exp(-M_PI * M_PI * kTau * kTau * f * f));
}

TEST(psd, WindowTilesAndHolesAreUnbiasedOnStationarySurfaces) {
  // One realisation's window-weighted mean square scatters about Sq^2 (the Hann window sees
  // ~1/4 of the scan's correlation areas: +-13 % for tau 5 um on 128 um, the seed above reads
  // +21 %); averaged over realisations the estimators are unbiased. 16 surfaces of 256^2,
  // tau 1.25 um (51 tau across): the integral and the power in discs of radius 0.75..2/(pi tau)
  // against the analytic sigma^2 (1 - exp(-(pi tau f)^2)), for the Hann window on the whole scan,
  // on tiles of 128 (9 tiles) and with a 10 % hole.
  constexpr int kSeeds = 16;
  const double tau = 1.25e-6;
  const std::vector<double> radii = {0.75, 1.0, 1.5, 2.0, 1e9};
  enum { kWhole, kTiles, kHole, kCases };
  std::vector<std::vector<double>> sum(kCases, std::vector<double>(radii.size(), 0.0));
  for (int seed = 1; seed <= kSeeds; ++seed) {
    Surface s = test_util::isotropic_gaussian(256, kDx, kSigma, tau, seed);
    PsdOptions tiles;
    tiles.tile = 128;
    const AreaPsd whole = areal_psd(s), tiled = areal_psd(s, tiles);
    EXPECT_EQ(tiled.tiles, 9u);  // starts 0, 64, 128 on each axis
    EXPECT_EQ(tiled.nfx, 128u);
    for (std::size_t iy = 60; iy < 141; ++iy)
      for (std::size_t ix = 90; ix < 171; ++ix) s.invalidate(s.index(ix, iy));
    const AreaPsd holed = areal_psd(s);
    const AreaPsd* psd[kCases] = {&whole, &tiled, &holed};
    for (int c = 0; c < kCases; ++c)
      for (std::size_t k = 0; k < radii.size(); ++k)
        sum[c][k] += psd[c]->power_within(radii[k] / (M_PI * tau)) / kSeeds;
  }
  const char* names[kCases] = {"whole scan", "tiles", "hole"};
  for (int c = 0; c < kCases; ++c)
    for (std::size_t k = 0; k < radii.size(); ++k) {
      const double want = kSigma * kSigma * (1 - std::exp(-radii[k] * radii[k]));
      std::printf("%s, disc %g/(pi tau): %.4f\n", names[c], radii[k], sum[c][k] / want);
      // The hole's hard edges are a second window: they move a few % of the power from small
      // discs outwards (the mask's spectrum smooths the estimate).
      const double tol[kCases] = {0.02, 0.03, 0.05};
      EXPECT_NEAR(sum[c][k] / want, 1.0, tol[c]) << names[c] << ", disc " << radii[k];
    }
}

TEST(psd, HannWindowStopsTheLeakageOfANonPeriodicScan) {
  // A 256^2 crop of the periodic surface is not periodic: without a window its edges leak
  // power along the frequency axes (~1/f^2), far above the Gaussian PSD (e^-(pi tau f)^2 ~ 0
  // there); the Hann window removes it.
  const Surface& big = gaussian_512();
  Surface crop(256, 256, kDx, kDx);
  for (std::size_t iy = 0; iy < 256; ++iy)
    for (std::size_t ix = 0; ix < 256; ++ix) crop.at(ix, iy) = big.at(ix + 100, iy + 50);
  PsdOptions none;
  none.window = PsdWindow::None;
  const AreaPsd raw = areal_psd(crop, none), hann = areal_psd(crop);
  const double f = 0.3 / kDx;  // 0.6 of Nyquist, on the fx axis
  const double leak_raw = raw.at(f, 0), leak_hann = hann.at(f, 0);
  EXPECT_GT(leak_raw, 1e6 * gaussian_psd(f));
  EXPECT_LT(leak_hann, 1e-3 * leak_raw) << leak_hann << " vs " << leak_raw;
}

TEST(psd, RealHeightsGiveASymmetricPsdAndInterpolationHitsTheNodes) {
  for (std::size_t n : {std::size_t{64}, std::size_t{65}}) {
    const Surface s = test_util::isotropic_gaussian(n, n + 2, kDx, kSigma, 1e-6, 11);
    const AreaPsd p = areal_psd(s);
    const double peak = *std::max_element(p.value.begin(), p.value.end());
    for (std::size_t iy = 1; iy < p.nfy; ++iy)
      for (std::size_t ix = 1; ix < p.nfx; ++ix) {
        // PSD(-f) = PSD(f) wherever the mirror node is on the grid.
        const long mx = 2 * static_cast<long>(p.nfx / 2) - static_cast<long>(ix);
        const long my = 2 * static_cast<long>(p.nfy / 2) - static_cast<long>(iy);
        if (mx < 0 || my < 0 || mx >= static_cast<long>(p.nfx) || my >= static_cast<long>(p.nfy))
          continue;
        const double v = p.at_node(ix, iy);
        ASSERT_NEAR(p.at_node(static_cast<std::size_t>(mx), static_cast<std::size_t>(my)), v,
                    1e-12 * peak);
        if (ix != p.nfx / 2 || iy != p.nfy / 2) {
          ASSERT_NEAR(p.at(p.fx(ix), p.fy(iy)), v, 1e-12 * peak);
        }
      }
    // Halfway between two nodes: their mean; beyond the band: 0.
    const double mid = p.at(p.fx(10) + 0.5 * p.dfx, p.fy(12));
    EXPECT_NEAR(mid, 0.5 * (p.at_node(10, 12) + p.at_node(11, 12)), 1e-12 * mid);
    EXPECT_EQ(p.at(1.01 / kDx, 0), 0.0);
    // At f = 0: the mean of the four nearest nodes (the node itself holds 0).
    const std::size_t cx = p.nfx / 2, cy = p.nfy / 2;
    EXPECT_NEAR(p.at(0, 0),
                0.25 * (p.at_node(cx - 1, cy) + p.at_node(cx + 1, cy) + p.at_node(cx, cy - 1) +
                        p.at_node(cx, cy + 1)),
                1e-12 * peak);
  }
}

TEST(psd, RefusedOverTheMemoryBudgetAndWithoutData) {
  const auto before = memory_budget();
  const bool was_explicit = memory_budget_is_explicit();
  set_memory_budget(1 << 20);
  EXPECT_THROW(areal_psd(gaussian_512(), {}, "scan.x3p"), FileError);
  set_memory_budget(before);
  if (!was_explicit) {
    EXPECT_NO_THROW(areal_psd(gaussian_512()));
  }
  Surface empty(8, 8, kDx, kDx);
  for (std::size_t i = 0; i < empty.size(); ++i) empty.invalidate(i);
  EXPECT_THROW(areal_psd(empty), InputError);
  EXPECT_THROW(areal_psd(Surface(1, 8, kDx, kDx)), InputError);
  EXPECT_THROW(parse_psd_window("hamming"), InputError);
}

TEST(psd, JsonRecordsUnitsAndNormalisation) {
  const nlohmann::json j = psd_json(areal_psd(gaussian_512()));
  EXPECT_EQ(j["frequency_unit"], "cycles/m");
  EXPECT_EQ(j["psd_unit"], "m^4");
  EXPECT_EQ(j["window"], "hann");
  EXPECT_NEAR(j["integral_m2"].get<double>() / std::pow(j["sq_m"].get<double>(), 2),
              j["integral_over_sq2"].get<double>(), 1e-12);
  EXPECT_DOUBLE_EQ(j["fx_max_per_m"].get<double>(), 256 / (512 * kDx));
}

// The default tile: 32 correlation lengths per axis when the scan is at least two of them long
// on each axis (three tiles with the 50 % overlap), else the whole scan
// (include/microbrdf/psd.hpp).
TEST(psd, DefaultTileFollowsTheCorrelationLength) {
  const PsdOptions a = default_psd_options(2240, 2240, 250e-9, 250e-9, 1e-6, 1e-6);
  EXPECT_EQ(a.tile, 128u);  // 32 um / 250 nm
  const PsdOptions b = default_psd_options(2240, 2240, 250e-9, 250e-9, 5e-6, 2e-6);
  EXPECT_EQ(b.tile, 640u);  // the longer-correlated axis decides
  const PsdOptions c = default_psd_options(2240, 2240, 250e-9, 250e-9, 20e-6, 20e-6);
  EXPECT_EQ(c.tile, 0u);  // 2560 samples: more than the scan
  const PsdOptions d = default_psd_options(1000, 1000, 1e-6, 1e-6, NAN, 3e-6);
  EXPECT_EQ(d.tile, 0u);
  EXPECT_NE(d.tile_why.find("longer than the scan"), std::string::npos) << d.tile_why;
  EXPECT_NE(a.tile_why.find("Welch"), std::string::npos) << a.tile_why;
  // The user's words.
  const Surface& s = gaussian_512();
  EXPECT_EQ(psd_options(s, PsdWindow::Hann, "whole").tile, 0u);
  EXPECT_EQ(psd_options(s, PsdWindow::None, "100").tile, 100u);
  EXPECT_EQ(psd_options(s, PsdWindow::None, "100").window, PsdWindow::None);
  EXPECT_THROW(psd_options(s, PsdWindow::Hann, "1"), InputError);
  EXPECT_THROW(psd_options(s, PsdWindow::Hann, "12x"), InputError);
  EXPECT_THROW(psd_options(s, PsdWindow::Hann, "often"), InputError);
}

// What the default tile is for: the whole-scan Hann periodogram of a Gaussian surface is
// exponential speckle about the analytic PSD pi tau^2 sigma^2 exp(-pi^2 tau^2 f^2) (median ln 2,
// spread of the ratio about 1); the Welch average over the default tiles brings the median to 1
// and the spread down by about the square root of the tile count.
TEST(psd, DefaultTilesAverageTheSpeckleOut) {
  const double tau = 1e-6, sigma = 2e-9;
  const Surface s = test_util::isotropic_gaussian(512, kDx, sigma, tau, 11);
  auto ratios = [&](const AreaPsd& p) {
    std::vector<double> r;
    for (std::size_t iy = 0; iy < p.nfy; ++iy)
      for (std::size_t ix = 0; ix < p.nfx; ++ix) {
        const double f = std::hypot(p.fx(ix), p.fy(iy));
        if (f == 0 || f * tau > 0.6) continue;  // the halo down to exp(-3.6) of its peak
        const double theory =
            M_PI * tau * tau * sigma * sigma * std::exp(-M_PI * M_PI * tau * tau * f * f);
        r.push_back(p.at_node(ix, iy) / theory);
      }
    std::sort(r.begin(), r.end());
    double m = 0, m2 = 0;
    for (double x : r) m += x;
    m /= static_cast<double>(r.size());
    for (double x : r) m2 += (x - m) * (x - m);
    return std::array<double, 3>{r[r.size() / 2], std::sqrt(m2 / static_cast<double>(r.size())) / m,
                                 static_cast<double>(r.size())};
  };
  const AreaPsd whole = areal_psd(s, psd_options(s, PsdWindow::Hann, "whole"));
  const AreaPsd tiled = areal_psd(s, default_psd_options(s));
  // tau as the scan's ACF reads it (1.00-1.03 um): tiles of 128-132 samples, 7 x 7 of them.
  EXPECT_GE(tiled.tile_nx, 128u);
  EXPECT_LE(tiled.tile_nx, 132u);
  EXPECT_EQ(tiled.tiles, 49u);
  const auto w = ratios(whole), t = ratios(tiled);
  std::printf(
      "whole scan: median %.3f, spread %.3f (%g nodes); tiled (%zu): median %.3f, spread "
      "%.3f (%g nodes)\n",
      w[0], w[1], w[2], tiled.tiles, t[0], t[1], t[2]);
  EXPECT_NEAR(w[0], std::log(2.0), 0.12);  // exponential: median ln 2 of the mean
  EXPECT_GT(w[1], 0.7);
  EXPECT_NEAR(t[0], 1.0, 0.1);
  EXPECT_LT(t[1], 0.3);
  EXPECT_GT(t[2], 30);
}
