// default_psd_options: the Welch tile a scan's PSD is averaged over when none is named
// (include/microbrdf/psd.hpp; docs/rayleigh_rice.md, "Tiles").
#include <cmath>
#include <cstdio>
#include <string>

#include "microbrdf/error.hpp"
#include "microbrdf/psd.hpp"
#include "microbrdf/statistics.hpp"

namespace microbrdf {

namespace {

// Tiles of this many correlation lengths: the Hann window's variance in q, (4/3) pi^2 / L^2 per
// axis, raises a Gaussian halo exp(-q^2 tau^2 / 4) at its 1e-3 level (q^2 tau^2 / 4 = ln 1000)
// by exp(ln(1000) (2/3) pi^2 (tau/L)^2) = exp(45.4 (tau/L)^2): 4.5 % at L = 32 tau.
constexpr double kTileInTau = 32;
// At least this many tiles per axis (50 % overlap: a side of 2 tiles holds 3).
constexpr double kMinSideInTiles = 2;

std::string um(double m) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g um", m * 1e6);
  return b;
}

}  // namespace

PsdOptions default_psd_options(std::size_t nx, std::size_t ny, double dx, double dy, double tau_x,
                               double tau_y) {
  PsdOptions o;
  const std::string whole =
      "one periodogram of the whole scan (exponential speckle: each node's "
      "standard deviation equals its mean)";
  if (!(std::isfinite(tau_x) && std::isfinite(tau_y) && tau_x > 0 && tau_y > 0)) {
    o.tile_why = whole + ": the correlation length is longer than the scan shows";
    return o;
  }
  // One side in samples long enough on both axes.
  // (less 1e-9: 32 x 5 um / 250 nm is 640, not 640 + rounding)
  const double t = std::max(std::ceil(kTileInTau * tau_x / dx - 1e-9),
                            std::ceil(kTileInTau * tau_y / dy - 1e-9));
  const double fits = std::min(static_cast<double>(nx), static_cast<double>(ny)) / t;
  const std::string tiles_of = std::to_string(static_cast<long long>(t)) + " samples (" +
                               um(t * dx) + " x " + um(t * dy) + ", " +
                               std::to_string(static_cast<int>(kTileInTau)) +
                               " x tau = " + um(tau_x) + " x " + um(tau_y) + ")";
  if (fits < kMinSideInTiles) {
    o.tile_why = whole + ": tiles of " + tiles_of + " need a scan of twice that per axis";
    return o;
  }
  o.tile = static_cast<std::size_t>(t);
  o.tile_why = "Welch average over tiles of " + tiles_of +
               " with 50 % overlap: the speckle of one periodogram averaged out, the Hann blur of "
               "the halo below 5 % at 1e-3 of its peak";
  return o;
}

PsdOptions default_psd_options(const Surface& s) {
  const SurfaceStats st = compute_stats(s);
  return default_psd_options(s.nx, s.ny, s.dx, s.dy, st.corr_length_x, st.corr_length_y);
}

PsdOptions psd_options(const Surface& s, PsdWindow window, const std::string& tile) {
  PsdOptions o;
  if (tile == "auto" && window == PsdWindow::None) {
    // No window is asked for periodic (generated) surfaces, whose whole-scan periodogram is
    // exact; a tile cut from them is not periodic and would leak along the axes.
    o.tile_why =
        "one periodogram of the whole scan (no window: exact for a periodic surface; a "
        "tile of it would leak along the axes)";
  } else if (tile == "auto") {
    o = default_psd_options(s);
  } else if (tile == "whole") {
    o.tile_why = "one periodogram of the whole scan (asked for)";
  } else {
    check_psd_tile(tile);
    o.tile = static_cast<std::size_t>(std::stoll(tile));
    o.tile_why = "Welch average over tiles of " + tile + " samples (asked for)";
  }
  o.window = window;
  return o;
}

void check_psd_tile(const std::string& tile) {
  if (tile == "auto" || tile == "whole") return;
  std::size_t used = 0;
  long long n = -1;
  try {
    n = std::stoll(tile, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != tile.size() || n < 2 || n > (1LL << 20))
    throw InputError("PSD tile '" + tile +
                     "': give auto, whole or a side in samples from 2 to 1048576");
}

}  // namespace microbrdf
