// Sun 2002 section 4: the free travel probability measured on generated 1-D Gaussian profiles.
//
// Units: tau = 1, sigma = 1/s, heights and distances in units of tau, positions in samples.
// For every zero crossing of the profile (in the middle part of each profile) a ray leaves
// the crossing point, at polar angle theta, once to +x and once to -x. The profile is
// piecewise linear between samples, so the ray (a straight line) is blocked iff some sample
// ahead lies at or above it; once the ray is above the profile's maximum it is free.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <tuple>

#include "core/splitmix64.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/generate.hpp"
#include "microbrdf/sun2002.hpp"

namespace microbrdf::sun2002 {
namespace {

constexpr std::size_t kBatch = 4096;  // samples per standard-error batch
constexpr std::size_t kBlock = 32;    // samples per block maximum (to skip free stretches)
constexpr std::size_t kMaxRows = 8;   // profiles per generate_profiles() call

using detail::splitmix64;

struct Crossing {
  std::size_t j;  // the profile crosses zero between samples j and j+1
  double xc;      // crossing position, samples
};

struct Row {
  const double* z = nullptr;
  std::size_t n = 0;
  double zmax = 0;
  std::vector<double> bmax;  // maximum of each kBlock-sample block
  std::vector<Crossing> crossings;
};

// Outcome of one ray: 0 = goes into the profile at once, 1 = leaves above then blocked,
// 2 = free, 3 = undecided (ran off the profile; cannot happen with the margins used).
int trace(const Row& r, const Crossing& c, double m, int dir) {
  // m: rise of the ray per sample (cot(theta) * dx); dir = +1 or -1.
  const double* z = r.z;
  if (dir > 0) {
    std::size_t k = c.j + 1;
    if (!(z[k] < (static_cast<double>(k) - c.xc) * m)) return 0;
    for (++k; k < r.n;) {
      const double ray = (static_cast<double>(k) - c.xc) * m;
      if (ray > r.zmax) return 2;
      const std::size_t b = k / kBlock;
      if (ray > r.bmax[b]) {  // the ray rises: above the whole rest of this block
        k = (b + 1) * kBlock;
        continue;
      }
      if (z[k] >= ray) return 1;
      ++k;
    }
    return 3;
  }
  std::size_t k = c.j;
  if (!(z[k] < (c.xc - static_cast<double>(k)) * m)) return 0;
  while (k-- > 0) {
    const double ray = (c.xc - static_cast<double>(k)) * m;
    if (ray > r.zmax) return 2;
    const std::size_t b = k / kBlock;
    if (ray > r.bmax[b]) {
      if (b == 0) return 3;
      k = b * kBlock;  // the loop's k-- moves to the last sample of block b - 1
      continue;
    }
    if (z[k] >= ray) return 1;
  }
  return 3;
}

struct Counts {
  std::uint32_t rays = 0, leaving = 0, free = 0;
};

// Ratio estimate num/den with its standard error from batch totals.
std::pair<double, double> ratio(const std::vector<Counts>& b, bool leaving) {
  double F = 0, R = 0;
  std::size_t nb = 0;
  for (const auto& c : b) {
    const double r = leaving ? c.leaving : c.rays;
    F += c.free;
    R += r;
    nb += r > 0;
  }
  if (R == 0) return {0, 0};
  const double g = F / R;
  double v = 0;
  for (const auto& c : b) {
    const double r = leaving ? c.leaving : c.rays;
    const double d = c.free - g * r;
    v += d * d;
  }
  const double se =
      nb > 1 ? std::sqrt(v * static_cast<double>(nb) / static_cast<double>(nb - 1)) / R : 0;
  return {g, se};
}

}  // namespace

FtpSimResult simulate_ftp(const FtpSimParams& p) {
  if (!(p.s > 0) || !std::isfinite(p.s)) throw InputError("FTP simulation: s must be positive");
  if (p.theta.empty()) throw InputError("FTP simulation: no angles given");
  for (double t : p.theta)
    if (!(t >= 0 && t <= M_PI / 2))
      throw InputError("FTP simulation: angles must be in [0, 90] deg");
  if (p.crossings < 1) throw InputError("FTP simulation: need at least one crossing");
  if (!(p.samples_per_tau >= 2 && p.samples_per_tau <= 1000))
    throw InputError("FTP simulation: samples per tau must be in [2, 1000]");
  if (p.profile_length < 1024)
    throw InputError("FTP simulation: profile length must be >= 1024 samples");

  const double sigma = 1 / p.s, dx = 1 / p.samples_per_tau;
  // Angles simulated (theta = pi/2 is exactly 0 and skipped).
  const double edge = M_PI / 2 - 1e-12;
  double tmax = 0;
  for (double t : p.theta)
    if (t < edge) tmax = std::max(tmax, std::tan(t));
  // A ray is decided once it is above the profile maximum: at most zmax tan(theta) away.
  // Margins for zmax = 6.5 sigma (exceeded with probability ~1e-10 per sample); crossings
  // whose ray would need more are skipped and counted in `excluded`.
  const double margin_d = std::ceil(6.5 * sigma * tmax / dx) + 2;
  if (margin_d > double(1u << 26))
    throw InputError(
        "FTP simulation: rays too close to grazing for this s (the profile margin would exceed "
        "2^26 samples)");
  const auto margin = static_cast<std::size_t>(margin_d);
  const std::size_t L = p.profile_length;
  const std::size_t n = L + 2 * margin;
  const std::size_t batches_per_profile = (L + kBatch - 1) / kBatch;

  // Expected crossings per profile (Rice: sqrt(2) / (pi tau) per unit length), to size calls.
  const double expect = std::sqrt(2.0) / M_PI * static_cast<double>(L) * dx;
  const std::size_t rows_per_call = std::clamp<std::size_t>(
      static_cast<std::size_t>(std::ceil(static_cast<double>(p.crossings) / expect)), 1, kMaxRows);

  FtpSimResult res;
  res.params = p;
  const std::size_t nt = p.theta.size();
  std::vector<std::vector<Counts>> counts(nt);
  std::vector<std::size_t> excluded(nt, 0);
  double slope_sum = 0;
  std::size_t slope_n = 0;

  for (std::uint64_t call = 0; res.crossings < p.crossings; ++call) {
    ProfileParams pp;
    pp.n = n;
    pp.rows = rows_per_call;
    pp.dx = dx;
    pp.sigma = sigma;
    pp.tau = 1;
    pp.seed = splitmix64(p.seed ^ splitmix64(call + 0x5eed));
    const Surface surf = generate_profiles(pp);

    std::vector<Row> rows(rows_per_call);
    std::vector<double> row_slope(rows_per_call, 0);
#pragma omp parallel for schedule(static)
    for (long ri = 0; ri < static_cast<long>(rows_per_call); ++ri) {
      Row& r = rows[static_cast<std::size_t>(ri)];
      r.z = surf.z.data() + static_cast<std::size_t>(ri) * n;
      r.n = n;
      r.zmax = *std::max_element(r.z, r.z + n);
      r.bmax.assign((n + kBlock - 1) / kBlock, -1e300);
      for (std::size_t k = 0; k < n; ++k) r.bmax[k / kBlock] = std::max(r.bmax[k / kBlock], r.z[k]);
      for (std::size_t j = margin; j < margin + L; ++j) {
        const double a = r.z[j], b = r.z[j + 1];
        if ((a < 0) != (b < 0)) r.crossings.push_back({j, static_cast<double>(j) + a / (a - b)});
        row_slope[static_cast<std::size_t>(ri)] += (b - a) * (b - a);
      }
    }
    const std::size_t base = counts[0].size();
    for (auto& c : counts) c.resize(base + rows_per_call * batches_per_profile);
    for (std::size_t ri = 0; ri < rows_per_call; ++ri) {
      res.crossings += rows[ri].crossings.size();
      slope_sum += row_slope[ri];
      slope_n += L;
    }
    res.profiles += rows_per_call;

    std::vector<std::size_t> excl(nt * rows_per_call, 0), undecided(nt * rows_per_call, 0);
#pragma omp parallel for collapse(2) schedule(dynamic)
    for (long ri = 0; ri < static_cast<long>(rows_per_call); ++ri) {
      for (long ti = 0; ti < static_cast<long>(nt); ++ti) {
        const Row& r = rows[static_cast<std::size_t>(ri)];
        const double theta = p.theta[static_cast<std::size_t>(ti)];
        auto& cnt = counts[static_cast<std::size_t>(ti)];
        const std::size_t b0 = base + static_cast<std::size_t>(ri) * batches_per_profile;
        if (theta >= edge) {
          // A horizontal ray from height 0: blocked by the first rise above 0. Not simulated.
          continue;
        }
        const double t = std::tan(theta);
        const double reach = t > 0 ? r.zmax * t / dx : 0;  // samples to rise above zmax
        const double m = t > 0 ? dx / t : 0;
        for (const auto& c : r.crossings) {
          Counts& k = cnt[b0 + (c.j - margin) / kBatch];
          if (c.xc - reach < 1 || c.xc + reach > static_cast<double>(n) - 2) {
            ++excl[static_cast<std::size_t>(ri) * nt + static_cast<std::size_t>(ti)];
            continue;
          }
          for (int dir : {+1, -1}) {
            ++k.rays;
            if (t == 0) {  // straight up: always leaves above and is free
              ++k.leaving;
              ++k.free;
              continue;
            }
            const int o = trace(r, c, m, dir);
            if (o >= 1) ++k.leaving;
            if (o == 2) ++k.free;
            if (o == 3)
              ++undecided[static_cast<std::size_t>(ri) * nt +
                          static_cast<std::size_t>(ti)];  // the margins prevent it
          }
        }
      }
    }
    for (std::size_t ri = 0; ri < rows_per_call; ++ri) {
      for (std::size_t ti = 0; ti < nt; ++ti) {
        if (undecided[ri * nt + ti])
          throw std::logic_error("FTP simulation: a ray ran off the profile");
        excluded[ti] += excl[ri * nt + ti];
      }
    }
  }

  res.slope_rms = slope_n ? std::sqrt(slope_sum / static_cast<double>(slope_n)) / dx : 0;
  for (std::size_t ti = 0; ti < nt; ++ti) {
    FtpSimPoint pt;
    pt.theta = p.theta[ti];
    for (const auto& c : counts[ti]) {
      pt.rays += c.rays;
      pt.rays_leaving += c.leaving;
      pt.free += c.free;
    }
    std::tie(pt.gamma_leaving, pt.se_leaving) = ratio(counts[ti], true);
    std::tie(pt.gamma_any, pt.se_any) = ratio(counts[ti], false);
    res.excluded = std::max(res.excluded, excluded[ti]);
    res.points.push_back(pt);
  }
  return res;
}

}  // namespace microbrdf::sun2002
