// The areal PSD of a scan (include/microbrdf/psd.hpp; docs/rayleigh_rice.md).
#include "microbrdf/psd.hpp"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "core/fft.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/memory_budget.hpp"

namespace microbrdf {
namespace {

// Hann weights sin^2(pi (i + 1/2) / n): symmetric about the tile centre, never exactly 0, so
// no valid sample is thrown away entirely.
std::vector<double> window_weights(PsdWindow w, std::size_t n) {
  std::vector<double> v(n, 1.0);
  if (w == PsdWindow::Hann)
    for (std::size_t i = 0; i < n; ++i) {
      const double s = std::sin(M_PI * (static_cast<double>(i) + 0.5) / static_cast<double>(n));
      v[i] = s * s;
    }
  return v;
}

// Start offsets of tiles of side t with 50 % overlap covering [0, n); the last one ends at n.
std::vector<std::size_t> tile_starts(std::size_t n, std::size_t t) {
  std::vector<std::size_t> s;
  const std::size_t step = std::max<std::size_t>(1, t / 2);
  for (std::size_t p = 0; p + t <= n; p += step) s.push_back(p);
  if (s.empty() || s.back() + t < n) s.push_back(n - t);
  return s;
}

}  // namespace

PsdWindow parse_psd_window(const std::string& name) {
  if (name == "none") return PsdWindow::None;
  if (name == "hann") return PsdWindow::Hann;
  throw InputError("unknown PSD window '" + name + "' (none or hann)");
}

std::string to_string(PsdWindow w) { return w == PsdWindow::Hann ? "hann" : "none"; }

double AreaPsd::integral() const {
  double sum = 0;
  for (double v : value) sum += v;
  return sum * dfx * dfy;
}

double AreaPsd::at(double fx_, double fy_) const {
  const double u = fx_ / dfx + static_cast<double>(nfx / 2);
  const double v = fy_ / dfy + static_cast<double>(nfy / 2);
  const double umax = static_cast<double>(nfx - 1), vmax = static_cast<double>(nfy - 1);
  if (!(u >= 0 && u <= umax && v >= 0 && v <= vmax)) return 0;
  // The cell's lower corner; the last node is a cell's upper corner, not a lower one.
  const auto ix = static_cast<std::size_t>(std::min(std::floor(u), std::max(0.0, umax - 1)));
  const auto iy = static_cast<std::size_t>(std::min(std::floor(v), std::max(0.0, vmax - 1)));
  const double tx = u - static_cast<double>(ix), ty = v - static_cast<double>(iy);
  const std::size_t ix1 = std::min(ix + 1, nfx - 1), iy1 = std::min(iy + 1, nfy - 1);
  const auto node = [&](std::size_t x, std::size_t y) {
    return x == nfx / 2 && y == nfy / 2 ? zero_frequency_estimate() : at_node(x, y);
  };
  return (1 - ty) * ((1 - tx) * node(ix, iy) + tx * node(ix1, iy)) +
         ty * ((1 - tx) * node(ix, iy1) + tx * node(ix1, iy1));
}

double AreaPsd::zero_frequency_estimate() const {
  const std::size_t cx = nfx / 2, cy = nfy / 2;
  double sum = 0;
  int n = 0;
  if (cx > 0) sum += at_node(cx - 1, cy), ++n;
  if (cx + 1 < nfx) sum += at_node(cx + 1, cy), ++n;
  if (cy > 0) sum += at_node(cx, cy - 1), ++n;
  if (cy + 1 < nfy) sum += at_node(cx, cy + 1), ++n;
  return n > 0 ? sum / n : 0.0;
}

double AreaPsd::power_within(double f_max) const {
  double sum = 0;
  for (std::size_t iy = 0; iy < nfy; ++iy)
    for (std::size_t ix = 0; ix < nfx; ++ix)
      if (std::hypot(fx(ix), fy(iy)) <= f_max) sum += at_node(ix, iy);
  return sum * dfx * dfy;
}

double AreaPsd::rms_slope() const {
  double sum = 0;
  for (std::size_t iy = 0; iy < nfy; ++iy)
    for (std::size_t ix = 0; ix < nfx; ++ix) {
      const double f2 = fx(ix) * fx(ix) + fy(iy) * fy(iy);
      sum += 4 * M_PI * M_PI * f2 * at_node(ix, iy);
    }
  return std::sqrt(sum * dfx * dfy);
}

AreaPsd areal_psd(const Surface& s, const PsdOptions& o, const std::string& what) {
  const std::size_t tnx = o.tile == 0 ? s.nx : std::min(o.tile, s.nx);
  const std::size_t tny = o.tile == 0 ? s.ny : std::min(o.tile, s.ny);
  if (tnx < 2 || tny < 2)
    throw InputError("the PSD needs at least 2 x 2 samples per tile (got " + std::to_string(tnx) +
                     " x " + std::to_string(tny) + ")");
  if (s.valid_count() == 0) throw InputError("the PSD needs valid samples (there are none)");
  // A tile's heights, FFTW's copy of them, the half spectrum and the two grids (sum, result).
  const std::uint64_t t = mul_sat(tnx, tny);
  check_memory(what, mul_sat(t, 8 * 2 + 16) + mul_sat(mul_sat(tnx, tny), 16),
               "the PSD's work arrays (" + std::to_string(tnx) + " x " + std::to_string(tny) +
                   " samples per tile)");
  AreaPsd p;
  p.nfx = tnx;
  p.nfy = tny;
  p.dx = s.dx;
  p.dy = s.dy;
  p.dfx = 1.0 / (static_cast<double>(tnx) * s.dx);
  p.dfy = 1.0 / (static_cast<double>(tny) * s.dy);
  p.window = o.window;
  p.tile_nx = tnx;
  p.tile_ny = tny;
  p.tile_why = o.tile_why;
  p.value.assign(tnx * tny, 0.0);

  const double mean = s.valid_mean();
  double m2 = 0;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (s.valid[i]) m2 += (s.z[i] - mean) * (s.z[i] - mean);
  p.sq = std::sqrt(m2 / static_cast<double>(s.valid_count()));

  const auto wx = window_weights(o.window, tnx), wy = window_weights(o.window, tny);
  const std::size_t hx = tnx / 2 + 1;
  double weight_sum = 0;  // sum over the tiles of sum_valid w^2
  std::vector<double> h(t);
  for (std::size_t y0 : tile_starts(s.ny, tny))
    for (std::size_t x0 : tile_starts(s.nx, tnx)) {
      double sw = 0, swh = 0, sw2 = 0;
      for (std::size_t iy = 0; iy < tny; ++iy)
        for (std::size_t ix = 0; ix < tnx; ++ix) {
          const std::size_t i = s.index(x0 + ix, y0 + iy);
          if (!s.valid[i]) continue;
          const double w = wx[ix] * wy[iy];
          sw += w;
          swh += w * s.z[i];
          sw2 += w * w;
        }
      if (sw2 == 0) continue;
      const double tile_mean = swh / sw;
      for (std::size_t iy = 0; iy < tny; ++iy)
        for (std::size_t ix = 0; ix < tnx; ++ix) {
          const std::size_t i = s.index(x0 + ix, y0 + iy);
          h[iy * tnx + ix] = s.valid[i] ? (s.z[i] - tile_mean) * wx[ix] * wy[iy] : 0.0;
        }
      const auto spec = detail::fft2_r2c(tnx, tny, h);
      // Sum of dx dy |H|^2 (the periodogram times sum w^2): the weights of the tile average.
      for (std::size_t jy = 0; jy < tny; ++jy)
        for (std::size_t jx = 0; jx < hx; ++jx) {
          const double v = std::norm(spec[jy * hx + jx]) * s.dx * s.dy;
          // Bin j of n is frequency index (j + n/2) mod n on the centred grid; the half
          // spectrum stands for its Hermitian mirror too (the self-mirrored bins once).
          const std::size_t cx = (jx + tnx / 2) % tnx, cy = (jy + tny / 2) % tny;
          p.value[cy * tnx + cx] += v;
          // A mirror inside the stored half (columns 0 and n/2) is visited on its own.
          const std::size_t mx = (tnx - jx) % tnx, my = (tny - jy) % tny;
          if (mx >= hx) p.value[((my + tny / 2) % tny) * tnx + (mx + tnx / 2) % tnx] += v;
        }
      weight_sum += sw2;
      ++p.tiles;
    }
  for (double& v : p.value) v /= weight_sum;
  // The mean was removed: the zero-frequency bin holds rounding only.
  p.value[(tny / 2) * tnx + tnx / 2] = 0;
  return p;
}

RadialPsd radial_psd(const AreaPsd& p) {
  RadialPsd r;
  const double df = std::max(p.dfx, p.dfy);
  const double fmax =
      std::min(static_cast<double>(p.nfx / 2) * p.dfx, static_cast<double>(p.nfy / 2) * p.dfy);
  const auto nb = static_cast<std::size_t>(std::floor(fmax / df)) + 1;
  std::vector<double> sum(nb, 0.0);
  std::vector<std::size_t> cnt(nb, 0);
  for (std::size_t iy = 0; iy < p.nfy; ++iy)
    for (std::size_t ix = 0; ix < p.nfx; ++ix) {
      const auto b = static_cast<std::size_t>(std::lround(std::hypot(p.fx(ix), p.fy(iy)) / df));
      if (b >= nb) continue;
      sum[b] += p.at_node(ix, iy);
      ++cnt[b];
    }
  for (std::size_t b = 0; b < nb; ++b) {
    if (cnt[b] == 0) continue;
    r.f.push_back(static_cast<double>(b) * df);
    r.value.push_back(sum[b] / static_cast<double>(cnt[b]));
    r.count.push_back(cnt[b]);
  }
  return r;
}

nlohmann::json psd_json(const AreaPsd& p) {
  return {
      {"convention", "ISO 25178-2 / ISO 10110-8 areal PSD, two-sided"},
      {"frequency_unit", "cycles/m"},
      {"psd_unit", "m^4"},
      {"normalisation",
       "PSD = dx dy |FFT(w h)|^2 / sum_valid w^2: sum(PSD) dfx dfy = the window-weighted mean "
       "square height (= Sq^2 exactly without a window on one tile; for a stationary "
       "surface Sq^2 in expectation with any window)"},
      {"zero_frequency", "0 (the window-weighted mean of each tile is removed)"},
      {"invalid_samples", "set to 0 after the mean is removed; normalised by sum_valid w^2"},
      {"nfx", p.nfx},
      {"nfy", p.nfy},
      {"dfx_per_m", p.dfx},
      {"dfy_per_m", p.dfy},
      {"fx_max_per_m", static_cast<double>(p.nfx / 2) * p.dfx},
      {"fy_max_per_m", static_cast<double>(p.nfy / 2) * p.dfy},
      {"window", to_string(p.window)},
      {"tile_nx", p.tile_nx},
      {"tile_ny", p.tile_ny},
      {"tiles", p.tiles},
      {"sq_m", p.sq},
      {"integral_m2", p.integral()},
      {"integral_over_sq2",
       p.sq > 0 ? nlohmann::json(p.integral() / (p.sq * p.sq)) : nlohmann::json(nullptr)},
      {"rms_slope", p.rms_slope()},
      {"tile_choice", p.tile_why.empty() ? nlohmann::json(nullptr) : nlohmann::json(p.tile_why)}};
}

}  // namespace microbrdf
