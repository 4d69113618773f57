// Effective NDFs from measured BRDFs, Dong 2015 eq. 9 (include/microbrdf/measured_ndf.hpp).
#include "microbrdf/measured_ndf.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>

#include "microbrdf/error.hpp"
#include "microbrdf/rgl_bsdf.hpp"
#include "microbrdf/tabulated_distribution.hpp"

namespace microbrdf {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void check(const EffectiveNdfOptions& o) {
  if (!(o.theta_d > 0 && o.theta_d < kPi)) throw InputError("theta_d must lie in (0, 180) deg");
  if (o.resolution < 5) throw InputError("resolution must be at least 5");
  if (!(o.wavelength_m > 0)) throw InputError("wavelength must be positive");
  if (!(o.kernel_sigma == 0 || (o.kernel_sigma > 0 && o.kernel_sigma <= kMaxKernelSigma)))
    throw InputError(fmt::format("the kernel width must lie in (0, {:.0f}] deg (got {:.4g} deg)",
                                 kMaxKernelSigma * 180 / kPi, o.kernel_sigma * 180 / kPi));
}

// The light and view directions at half vector h, theta_d apart, at equal elevation.
void pair_at(const Vec3& h, double half, Vec3& wi, Vec3& wo) {
  const double r = std::hypot(h.x(), h.y());
  const Vec3 b = r > 1e-12 ? Vec3(-h.y() / r, h.x() / r, 0) : Vec3(0, 1, 0);
  wi = std::cos(half) * h + std::sin(half) * b;
  wo = std::cos(half) * h - std::sin(half) * b;
}

// A distribution made of the measured part of a G = 1 estimate (for its Smith G2).
std::shared_ptr<TabulatedDistribution> distribution_of(const TabulatedNdf& t) {
  TabulatedNdf filled = t;
  for (double& v : filled.values())
    if (!(v > 0)) v = 0;
  return std::make_shared<TabulatedDistribution>(std::move(filled));
}

std::string g_note(bool smith) {
  return smith ? "G = height-correlated Smith G2 of the estimate (two fixed-point steps)"
               : "G = 1 (Dong's assumption)";
}

}  // namespace

std::size_t measured_nodes(const TabulatedNdf& t) {
  std::size_t n = 0;
  for (std::size_t iy = 0; iy < t.resolution(); ++iy)
    for (std::size_t ix = 0; ix < t.resolution(); ++ix) {
      const double x = t.node_x(ix), y = t.node_y(iy);
      if (x * x + y * y < 1 && std::isfinite(t.at(ix, iy))) ++n;
    }
  return n;
}

TabulatedNdf effective_ndf(const Brdf& brdf, const Fresnel& fresnel, const EffectiveNdfOptions& o) {
  check(o);
  const double half = o.theta_d / 2;
  const double F = fresnel.eval(std::cos(half), o.wavelength_m);  // wi.h is the same everywhere
  if (!(F > 0)) throw InputError("the Fresnel term is 0 at theta_d / 2");
  const std::size_t n = o.resolution;
  TabulatedNdf t(n);
  std::shared_ptr<TabulatedDistribution> g;
  for (int pass = 0; pass < (o.smith ? 3 : 1); ++pass) {
    TabulatedNdf next(n);
#pragma omp parallel for schedule(dynamic, 4)
    for (std::size_t iy = 0; iy < n; ++iy)
      for (std::size_t ix = 0; ix < n; ++ix) {
        const double x = next.node_x(ix), y = next.node_y(iy), r2 = x * x + y * y;
        if (r2 >= 1) continue;
        const Vec3 h(x, y, std::sqrt(1 - r2));
        Vec3 wi, wo;
        pair_at(h, half, wi, wo);
        const double f = brdf.eval(wi, wo, o.wavelength_m);
        double d = std::isnan(f) ? kNaN : 4 * wi.z() * wo.z() * f / F;
        if (g && std::isfinite(d)) {
          const double g2 = g->G2(wi, wo, h);
          d = g2 > 0 ? d / g2 : kNaN;
        }
        next.at(ix, iy) = d;
      }
    t = std::move(next);
    if (o.smith && pass < 2) g = distribution_of(t);
  }
  t.meta.method = "measured";
  t.meta.wavelength_m = o.wavelength_m;
  t.meta.samples_used = measured_nodes(t);
  t.meta.notes = fmt::format(
      "Dong eq. 9 from a full BRDF ({}) at theta_d = {:.4g} deg (wi.h = {:.6f}), F(wi.h) = {:.6g}; "
      "{}; NaN = unmeasured",
      brdf.describe(), o.theta_d * 180 / kPi, std::cos(half), F, g_note(o.smith));
  return t;
}

TabulatedNdf effective_ndf(const GonioData& data, const Fresnel& fresnel,
                           const EffectiveNdfOptions& o) {
  check(o);
  // The wavelength nearest the requested one, and the points measured at it (within 0.5 nm).
  double best = kNaN;
  for (const auto& p : data.points)
    if (std::isnan(best) ||
        std::abs(p.wavelength_m - o.wavelength_m) < std::abs(best - o.wavelength_m))
      best = p.wavelength_m;
  struct Pt {
    Vec3 wi, wo, h;
    double d;
  };
  std::vector<Pt> pts;
  std::size_t skipped = 0;
  for (const auto& p : data.points) {
    if (std::abs(p.wavelength_m - best) > 0.5e-9) continue;
    const Vec3 wi = p.wi(), wo = p.wo();
    if (wi.z() <= 1e-9 || wo.z() <= 1e-9 || (wi + wo).norm() < 1e-9) {
      ++skipped;
      continue;
    }
    const Vec3 h = (wi + wo).normalized();
    const double F = fresnel.eval(wi.dot(h), p.wavelength_m);
    if (!(F > 0)) {
      ++skipped;
      continue;
    }
    pts.push_back({wi, wo, h, 4 * wi.z() * wo.z() * p.brdf / F});
  }
  if (pts.empty())
    throw InputError("no goniometer point with both directions above the horizon at " +
                     fmt::format("{:.1f} nm", best * 1e9));
  // Kernel width: the median nearest-neighbour distance of the half vectors on the disk
  // (estimated on at most 4000 points, against all points).
  double s = o.kernel_sigma;
  if (!(s > 0)) {
    std::vector<std::size_t> order(pts.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return pts[a].h.x() < pts[b].h.x(); });
    std::vector<double> nn;
    const std::size_t stride = std::max<std::size_t>(1, order.size() / 4000);
    for (std::size_t k = 0; k < order.size(); k += stride) {
      const Vec3& a = pts[order[k]].h;
      double d2 = std::numeric_limits<double>::infinity();
      for (std::size_t j = k + 1; j < order.size(); ++j) {
        const Vec3& b = pts[order[j]].h;
        const double dx = b.x() - a.x();
        if (dx * dx >= d2) break;
        d2 = std::min(d2, dx * dx + (b.y() - a.y()) * (b.y() - a.y()));
      }
      for (std::size_t j = k; j-- > 0;) {
        const Vec3& b = pts[order[j]].h;
        const double dx = a.x() - b.x();
        if (dx * dx >= d2) break;
        d2 = std::min(d2, dx * dx + (b.y() - a.y()) * (b.y() - a.y()));
      }
      if (std::isfinite(d2) && d2 > 0) nn.push_back(std::sqrt(d2));
    }
    if (nn.empty()) throw InputError("the goniometer points share one half vector");
    std::nth_element(nn.begin(), nn.begin() + nn.size() / 2, nn.end());
    s = nn[nn.size() / 2];
  }
  const std::size_t n = o.resolution;
  const double delta = 2.0 / double(n - 1);
  std::shared_ptr<TabulatedDistribution> g;
  TabulatedNdf t(n);
  for (int pass = 0; pass < (o.smith ? 3 : 1); ++pass) {
    std::vector<double> wsum(n * n, 0.0), dsum(n * n, 0.0);
    const long reach = static_cast<long>(std::ceil(3 * s / delta));
    for (const auto& p : pts) {
      double d = p.d;
      if (g) {
        const double g2 = g->G2(p.wi, p.wo, p.h);
        if (!(g2 > 0)) continue;
        d /= g2;
      }
      const long cx = std::lround((p.h.x() + 1) / delta), cy = std::lround((p.h.y() + 1) / delta);
      for (long iy = std::max(0L, cy - reach); iy <= std::min(long(n) - 1, cy + reach); ++iy)
        for (long ix = std::max(0L, cx - reach); ix <= std::min(long(n) - 1, cx + reach); ++ix) {
          const double dx = -1 + delta * double(ix) - p.h.x(),
                       dy = -1 + delta * double(iy) - p.h.y();
          const double w = std::exp(-(dx * dx + dy * dy) / (2 * s * s));
          wsum[std::size_t(iy) * n + std::size_t(ix)] += w;
          dsum[std::size_t(iy) * n + std::size_t(ix)] += w * d;
        }
    }
    const double wmin = std::exp(-2.0);
    for (std::size_t iy = 0; iy < n; ++iy)
      for (std::size_t ix = 0; ix < n; ++ix) {
        const double x = t.node_x(ix), y = t.node_y(iy);
        const std::size_t k = iy * n + ix;
        t.at(ix, iy) = x * x + y * y >= 1 ? 0.0 : wsum[k] >= wmin ? dsum[k] / wsum[k] : kNaN;
      }
    if (o.smith && pass < 2) g = distribution_of(t);
  }
  if (measured_nodes(t) == 0)
    throw InputError(fmt::format(
        "no node of the {} x {} table lies within two kernel widths ({:.3g} deg) of a goniometer "
        "point: nothing is measured (a wider --kernel or a finer --resolution)",
        n, n, s * 180 / kPi));
  t.meta.method = "measured";
  t.meta.wavelength_m = best;
  t.meta.samples_used = pts.size();
  t.meta.samples_skipped = skipped;
  t.meta.notes = fmt::format(
      "Dong eq. 9 from {} goniometer points at {:.1f} nm, splatted with a Gaussian kernel of "
      "std {:.4g} (disk coordinates, {:.3g} deg near the pole); nodes with summed weight below "
      "exp(-2) are NaN (unmeasured); {}",
      pts.size(), best * 1e9, s, s * 180 / kPi, g_note(o.smith));
  return t;
}

std::shared_ptr<MicrofacetDistribution> lobe_distribution(const Brdf& brdf, std::size_t resolution,
                                                          double wavelength_m) {
  EffectiveNdfOptions o;
  o.resolution = resolution;
  o.wavelength_m = wavelength_m;
  TabulatedNdf t = effective_ndf(brdf, PerfectMirrorFresnel(), o);
  // One grid serves every incidence, but a wave-optics lobe changes width with it (D_K at
  // lambda_q = lambda / cos(theta_d / 2) widens towards grazing): the envelope (node-wise
  // maximum, each read normalised to its sum) of eq. 9 read at theta_d 14, 90 and 140 deg.
  auto normalise = [](TabulatedNdf& x) {
    double sum = 0;
    for (double v : x.values())
      if (std::isfinite(v) && v > 0) sum += v;
    if (sum > 0)
      for (double& v : x.values()) v = std::isfinite(v) ? v / sum : v;
  };
  normalise(t);
  for (double theta_d_deg : {90.0, 140.0}) {
    o.theta_d = theta_d_deg * M_PI / 180;
    TabulatedNdf u = effective_ndf(brdf, PerfectMirrorFresnel(), o);
    normalise(u);
    for (std::size_t k = 0; k < t.values().size(); ++k)
      if (std::isfinite(u.values()[k]) && !(t.values()[k] >= u.values()[k]))
        t.values()[k] = u.values()[k];
  }
  double vmax = 0;
  for (double v : t.values())
    if (v > vmax) vmax = v;
  if (!(vmax > 0) || !std::isfinite(vmax))
    throw InputError("the BRDF has no positive value at theta_d = 14.14 deg: no lobe to follow");
  // A specular spike (a smooth surface's coherent reflection: one node holding most of the
  // mass) would draw nearly every sample of a grid that follows this lobe, leaving its diffuse
  // halo a node or two: the lobe is capped, halving the cap until the nodes at the cap hold at
  // most 30 % of the capped mass. A lobe without a spike is left as it is.
  double cap = vmax;
  for (int halvings = 0; halvings < 60; ++halvings) {
    double at_cap = 0, total = 0;
    for (double v : t.values()) {
      if (!std::isfinite(v) || v <= 0) continue;
      total += std::min(v, cap);
      if (v >= cap) at_cap += cap;
    }
    if (at_cap <= 0.3 * total) break;
    cap *= 0.5;
  }
  for (std::size_t iy = 0; iy < t.resolution(); ++iy)
    for (std::size_t ix = 0; ix < t.resolution(); ++ix) {
      const double x = t.node_x(ix), y = t.node_y(iy);
      double& v = t.at(ix, iy);
      v = x * x + y * y >= 1 ? 0.0 : std::clamp(std::isfinite(v) ? v : 0.0, 1e-4 * cap, cap);
    }
  t.meta.method = "lobe";
  return std::make_shared<TabulatedDistribution>(std::move(t));
}

namespace {
std::string lower_extension(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  for (auto& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}
}  // namespace

std::unique_ptr<Brdf> read_measured_brdf(const std::string& path) {
  const std::string e = lower_extension(path);
  if (e == ".binary") return std::make_unique<MerlBrdf>(read_merl(path), path);
  if (e == ".bsdf") return std::make_unique<RglBrdf>(RglBrdf::load(path));
  if (e == ".csv")
    throw InputError(path + ": a goniometer point set is not a full BRDF (use `measured ndf`)");
  throw InputError(path + ": unknown measured-BRDF type (use .binary MERL or .bsdf RGL)");
}

TabulatedNdf measured_ndf_file(const std::string& path, const Fresnel& fresnel,
                               const EffectiveNdfOptions& options) {
  check(options);  // the options' errors are the caller's, not the file's
  const std::string e = lower_extension(path);
  TabulatedNdf t;
  if (e == ".csv") {
    const GonioData data = read_gonio_csv(path);
    // What the points cannot give (none above the horizon, one half vector) is the file's.
    t = about_file(path, [&] { return effective_ndf(data, fresnel, options); });
  } else if (e == ".binary" || e == ".bsdf") {
    t = effective_ndf(*read_measured_brdf(path), fresnel, options);
    if (measured_nodes(t) == 0)
      throw FileError(path, fmt::format("the file holds no valid BRDF value at theta_d = {:.4g} "
                                        "deg (every node of the table would be NaN: unmeasured)",
                                        options.theta_d * 180 / kPi));
  } else {
    throw InputError(path +
                     ": unknown measured-BRDF type (use .csv goniometer points, .binary MERL or "
                     ".bsdf RGL)");
  }
  // A BRDF is never negative: negative values (a background subtracted too far) are the
  // file's, and an NDF made of them could not be written.
  std::size_t negative = 0, measured = 0;
  double lowest = 0;
  for (double v : t.values())
    if (std::isfinite(v)) {
      ++measured;
      if (v < 0) ++negative, lowest = std::min(lowest, v);
    }
  if (negative > 0)
    throw FileError(path, fmt::format("the BRDF is negative at {} of the {} table nodes it gives "
                                      "(down to D = {:.4g}): a BRDF cannot be negative",
                                      negative, measured, lowest));
  t.meta.sources = {path};
  return t;
}

std::string wavelength_warning(const TabulatedNdf& t, double requested_m, const std::string& path) {
  if (!(std::abs(t.meta.wavelength_m - requested_m) > 0.5e-9)) return "";
  return fmt::format(
      "{}: warning: measured at {:.1f} nm, not at the requested {:.1f} nm; the "
      "table is the {:.1f} nm measurement (--wavelength chooses)",
      path, t.meta.wavelength_m * 1e9, requested_m * 1e9, t.meta.wavelength_m * 1e9);
}

}  // namespace microbrdf
