// Visibility statistics by ray tracing a micro-scene: Smith's G1 (Dong 2015 Fig. 6 left) and
// Sun 2002's free travel probability on 2-D surfaces.
#include <omp.h>

#include <cmath>

#include "microbrdf/error.hpp"
#include "microbrdf/simulate.hpp"

namespace microbrdf {
namespace {

using Vec = Eigen::Vector3d;

// A surface point under a uniform point of the tile (first hit of a vertical ray from the top).
bool surface_point(const MicroScene& sc, SimRng& rng, MicroHit& h) {
  const Vec o(rng.uniform() * sc.width(), rng.uniform() * sc.height(), sc.zmax());
  return sc.trace(o, Vec(0, 0, -1), h) == TraceEnd::Hit;
}

// Weighted Bernoulli mean over threads in fixed blocks (deterministic for a thread count).
template <class Sample>
FractionEstimate weighted_fraction(std::uint64_t samples, std::uint64_t seed, Sample&& sample) {
  if (samples < 1 || samples > (std::uint64_t{1} << 32))
    throw InputError("visibility samples per angle must lie in 1..4294967296 (got " +
                     std::to_string(samples) + "; --visibility-samples)");
  const std::int64_t blocks = static_cast<std::int64_t>((samples + 255) / 256);
  double sw = 0, swv = 0, sw2 = 0, sw2v = 0;
  std::uint64_t n = 0;
#pragma omp parallel for schedule(static) reduction(+ : sw, swv, sw2, sw2v, n)
  for (std::int64_t b = 0; b < blocks; ++b) {
    SimRng rng(seed, static_cast<std::uint64_t>(b));
    for (int i = 0; i < 256; ++i) {
      double w = 0;
      bool visible = false;
      if (!sample(rng, w, visible) || !(w > 0)) continue;
      ++n;
      sw += w;
      sw2 += w * w;
      if (visible) {
        swv += w;
        sw2v += w * w;
      }
    }
  }
  FractionEstimate e;
  e.samples = n;
  if (sw > 0) {
    e.value = swv / sw;
    // Ratio estimator: var = sum w^2 (v - p)^2 / (sum w)^2.
    const double p = e.value;
    const double var = (sw2v * (1 - p) * (1 - p) + (sw2 - sw2v) * p * p) / (sw * sw);
    e.std_error = std::sqrt(std::max(0.0, var));
  }
  return e;
}

}  // namespace

FractionEstimate visible_fraction(const MicroScene& sc, double theta, std::uint64_t samples,
                                  std::uint64_t seed) {
  const double st = std::sin(theta), ct = std::cos(theta), eps = sc.epsilon();
  return weighted_fraction(samples, seed, [&](SimRng& rng, double& w, bool& visible) {
    MicroHit h;
    if (!surface_point(sc, rng, h)) return false;
    const double phi = 2 * M_PI * rng.uniform();
    const Vec v = sc.to_scene(Vec(st * std::cos(phi), st * std::sin(phi), ct));
    const double vn = v.dot(h.n);
    if (!(vn > 0) || !(h.n.z() > 0)) return false;
    w = vn / h.n.z();  // projected area towards v per unit of the mean plane
    MicroHit h2;
    visible = sc.trace(h.p + eps * h.n, v, h2) == TraceEnd::EscapedUp;
    return true;
  });
}

FractionEstimate free_travel_probability(const MicroScene& sc, double theta, double band,
                                         std::uint64_t samples, std::uint64_t seed) {
  const double st = std::sin(theta), ct = std::cos(theta), eps = sc.epsilon();
  return weighted_fraction(samples, seed, [&](SimRng& rng, double& w, bool& visible) {
    MicroHit h;
    // Rejection: points within the band around the mean plane.
    for (int tries = 0; tries < 1000; ++tries) {
      if (!surface_point(sc, rng, h)) return false;
      if (std::abs(h.p.z()) <= band) break;
      if (tries == 999) return false;
    }
    const double phi = 2 * M_PI * rng.uniform();
    const Vec v = sc.to_scene(Vec(st * std::cos(phi), st * std::sin(phi), ct));
    if (!(v.dot(h.n) > 0)) return false;  // the facet faces the ray
    w = 1;
    MicroHit h2;
    visible = sc.trace(h.p + eps * h.n, v, h2) == TraceEnd::EscapedUp;
    return true;
  });
}

}  // namespace microbrdf
