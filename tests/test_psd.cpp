// The areal PSD of a scan (include/microbrdf/psd.hpp): normalisation, the analytic PSD of a
// generated Gaussian surface, symmetry, interpolation, tiles, invalid samples, memory budget.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

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

TEST(psd, IntegralIsSqSquaredForEveryEstimator) {
  Surface s = test_util::isotropic_gaussian(200, 150, kDx, kSigma, 1e-6, 3);
  for (std::size_t i = 0; i < s.size(); i += 7) s.z[i] += 2e-9 * std::sin(0.3 * i);  // not periodic
  for (std::size_t i = 4000; i < 4300; ++i) s.invalidate(i);
  const double sq = sq_of(s);
  for (auto w : {PsdWindow::None, PsdWindow::Hann})
    for (std::size_t tile : {std::size_t{0}, std::size_t{64}}) {
      PsdOptions o;
      o.window = w;
      o.tile = tile;
      const AreaPsd p = areal_psd(s, o);
      EXPECT_NEAR(p.integral() / (sq * sq), 1.0, 1e-12) << to_string(w) << " tile " << tile;
      EXPECT_NEAR(p.sq, sq, 1e-15);
      EXPECT_EQ(p.at_node(p.nfx / 2, p.nfy / 2), 0.0);  // the zero-frequency bin
      // Without a window the raw periodogram of one fully valid tile already integrates to
      // its mean square; with the hole and the sine, the correction stays near 1.
      EXPECT_NEAR(p.power_correction, 1.0, 0.1);
    }
}

TEST(psd, PeriodogramNeedsNoCorrectionWithoutWindow) {
  PsdOptions o;
  o.window = PsdWindow::None;
  const AreaPsd p = areal_psd(gaussian_512(), o);
  EXPECT_NEAR(p.power_correction, 1.0, 1e-12);
  EXPECT_EQ(p.tiles, 1u);
  EXPECT_DOUBLE_EQ(p.dfx, 1 / (512 * kDx));
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
}

// The power within |f| < F: sigma^2 (1 - exp(-pi^2 tau^2 F^2)) for the analytic PSD.
double analytic_power_within(double f) {
  return kSigma * kSigma * (1 - std::exp(-M_PI * M_PI * kTau * kTau * f * f));
}

TEST(psd, HannEstimateIsUnbiased) {
  // The Hann window mixes neighbouring coefficients (three taps per axis), so one realisation's
  // nodes and even small discs of them scatter by 10-20 %; averaged over realisations the power
  // in discs is the analytic one (tau = 2.5 um on 256^2: the same tau / scan ratio as above).
  // Discs from 6 nodes in radius: the window's main lobe (+-1 node per axis) takes power out of
  // the nodes next to zero frequency when the mean is removed (a disc of 4 nodes is 14 % low).
  constexpr int kSeeds = 24;
  const double tau = 0.5 * kTau;
  const std::vector<double> radii = {0.75, 1.0, 1.5, 2.0};
  std::vector<double> sum(radii.size(), 0.0);
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const AreaPsd p = areal_psd(test_util::isotropic_gaussian(256, kDx, kSigma, tau, seed));
    for (std::size_t k = 0; k < radii.size(); ++k)
      sum[k] += p.power_within(radii[k] / (M_PI * tau)) / kSeeds;
  }
  for (std::size_t k = 0; k < radii.size(); ++k) {
    const double want = kSigma * kSigma * (1 - std::exp(-radii[k] * radii[k]));
    EXPECT_NEAR(sum[k] / want, 1.0, 0.04) << "disc radius " << radii[k] << " / (pi tau)";
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

TEST(psd, TilesAverageAndMissingSamplesDoNotBiasThePsd) {
  const Surface& full = gaussian_512();
  PsdOptions o;
  o.tile = 128;
  const AreaPsd small = areal_psd(full, o);
  EXPECT_EQ(small.tiles, 49u);  // starts 0, 64, ..., 384 on each axis
  EXPECT_EQ(small.nfx, 128u);
  o.tile = 256;
  const AreaPsd tiled = areal_psd(full, o);
  EXPECT_EQ(tiled.tiles, 9u);
  // A 10 % hole, or tiles: the power in discs stays within 5 % of the analytic one.
  Surface holed = full;
  for (std::size_t iy = 100; iy < 260; ++iy)
    for (std::size_t ix = 200; ix < 360; ++ix) holed.invalidate(holed.index(ix, iy));
  const AreaPsd h = areal_psd(holed);
  // (Discs wide enough for the tiles' coarser frequency step, 1 / (256 dx); each tile's mean
  // removal takes the power below that step out, pi tau^2 df^2 = 2 % here.)
  for (double f : {1.5 / (M_PI * kTau), 2.0 / (M_PI * kTau)}) {
    EXPECT_NEAR(h.power_within(f) / analytic_power_within(f), 1.0, 0.05) << "hole, f " << f;
    EXPECT_NEAR(tiled.power_within(f) / analytic_power_within(f), 1.0, 0.05) << "tiles, f " << f;
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
  EXPECT_NEAR(j["integral_m2"].get<double>() / std::pow(j["sq_m"].get<double>(), 2), 1, 1e-12);
  EXPECT_DOUBLE_EQ(j["fx_max_per_m"].get<double>(), 256 / (512 * kDx));
}
