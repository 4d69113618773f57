// The microfacet random walk (include/microbrdf/multiple_scattering.hpp; Heitz et al. 2016,
// conductor case, uniform height distribution: C1(h) = (h + 1)/2 on [-1, 1]).
//
// The walk never needs the height itself, only c = C1(h) in [0, 1] (c = 1 above the surface),
// so it carries c.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "core/splitmix64.hpp"
#include "microbrdf/multiple_scattering.hpp"
#include "microbrdf/tabulated_distribution.hpp"

namespace microbrdf {
namespace {

// Directions closer to the horizon than this are treated as horizontal: the ray meets the
// microsurface where it is (Lambda -> infinity).
constexpr double kHorizon = 1e-9;
// Tries of the rejection step for an upward ray before the walk is dropped (the acceptance is
// sigma+(v) / sigma+(v') > 0; 256 tries fail with probability < 1e-9 down to 8 % acceptance).
constexpr int kMaxTries = 256;

Vec3 reflect(const Vec3& d, const Vec3& m) { return d - 2 * d.dot(m) * m; }

double fresnel_of(const Fresnel* f, double cos_i, double wavelength_m) {
  return f ? f->eval(cos_i, wavelength_m) : 1.0;
}

}  // namespace

double WalkRng::next() {
  state_ += 0x9E3779B97F4A7C15ull;
  std::uint64_t z = state_;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1.0p-53;
}

MicrofacetRandomWalk::MicrofacetRandomWalk(std::shared_ptr<const MicrofacetDistribution> d,
                                           int max_order)
    : d_(std::move(d)), max_order_(max_order) {
  if (!d_) throw std::invalid_argument("MicrofacetRandomWalk needs a distribution");
  if (max_order_ < 1) throw std::invalid_argument("MicrofacetRandomWalk: max_order must be >= 1");
  weighted_ = dynamic_cast<const TabulatedDistribution*>(d_.get()) != nullptr;
}

double MicrofacetRandomWalk::lambda(const Vec3& v) const {
  // Clamped to >= 0: only a skewed ellipsoid (or a tabulated NDF with a mean slope) has
  // Lambda < 0, where the walk's escape probability C1^Lambda would exceed 1.
  if (v.z() > 0) return std::max(0.0, d_->lambda(v));
  return -1.0 - std::max(0.0, d_->lambda(-v));
}

double MicrofacetRandomWalk::sigma(const Vec3& v) const {
  // Projected area of the microsurface seen from v: v.z (1 + Lambda(v)) for any v (for v.z < 0
  // this is |v.z| Lambda(-v), the back-facing facets' share).
  const double z =
      std::abs(v.z()) < kHorizon ? std::copysign(kHorizon, v.z() == 0 ? 1 : v.z()) : v.z();
  const Vec3 u = Vec3(v.x(), v.y(), z).normalized();
  return u.z() * (1.0 + lambda(u));
}

bool MicrofacetRandomWalk::next_height(const Vec3& wr, double& c1, WalkRng& rng) const {
  if (wr.z() > kHorizon) {
    const double l = lambda(wr);
    if (!(l > 0)) return false;  // G1 = 1: it leaves
    const double g1 = std::pow(c1, l);
    const double u = rng.next();
    if (u >= 1.0 - g1) return false;
    c1 = std::min(1.0, c1 / std::pow(1.0 - u, 1.0 / l));
    return true;
  }
  if (wr.z() < -kHorizon) {
    const double l = lambda(-wr);
    c1 *= std::pow(1.0 - rng.next(), 1.0 / (1.0 + l));  // 1 - U in (0, 1]: c1 stays > 0
    return true;
  }
  return true;  // horizontal: meets the surface where it is
}

bool MicrofacetRandomWalk::sample_normal(const Vec3& wr, double u1, double u2, WalkRng& rng,
                                         Vec3& m, double& w) const {
  const Vec3 v = -wr;  // the facet is seen from v
  if (v.z() > kHorizon) {
    m = d_->sample_visible(v, u1, u2);
    if (!(v.dot(m) > 0)) return false;
    w = 1;
    if (weighted_) {
      const double q = d_->sampling_pdf(v, m);
      if (!(q > 0)) return false;
      w = d_->pdf_visible(v, m) / q;
    }
    return true;
  }
  // v at or below the horizon (the ray travels up): the visible normals of v, <v.m>+ D(m), by
  // rejection from those of its mirror image v' = (v.x, v.y, |v.z|): <v.m>+ <= <v'.m>+ for every
  // m with m.z > 0.
  const Vec3 vp = Vec3(v.x(), v.y(), std::max(std::abs(v.z()), kHorizon)).normalized();
  for (int t = 0; t < kMaxTries; ++t) {
    if (t > 0) {
      u1 = rng.next();
      u2 = rng.next();
    }
    const Vec3 c = d_->sample_visible(vp, u1, u2);
    const double a = v.dot(c), b = vp.dot(c);
    if (!(a > 0 && b > 0) || rng.next() * b >= a) continue;
    m = c;
    w = 1;
    if (weighted_) {
      const double q = d_->sampling_pdf(vp, m);
      if (!(q > 0)) return false;
      w = d_->pdf_visible(vp, m) / q;
    }
    return true;
  }
  return false;
}

double MicrofacetRandomWalk::phase(const Vec3& v, const Vec3& wo, const Fresnel* fresnel,
                                   double wavelength_m, double sigma_v) const {
  // Conductor phase function: F D_v(h) / (4 v.h) = F D(h) / (4 sigma+(v)), h the half vector.
  const Vec3 hs = v + wo;
  const double len = hs.norm();
  if (!(len > 0)) return 0;
  const Vec3 h = hs / len;
  const double vh = v.dot(h);
  if (h.z() <= 0 || vh <= 0) return 0;
  return fresnel_of(fresnel, vh, wavelength_m) * d_->D(h) / (4 * sigma_v);
}

std::optional<MicrofacetRandomWalk::Exit> MicrofacetRandomWalk::sample(const Vec3& wi, double u1,
                                                                       double u2, WalkRng& rng,
                                                                       const Fresnel* fresnel,
                                                                       double wavelength_m) const {
  if (!(wi.z() > 0)) return std::nullopt;
  Vec3 wr = -wi;
  double c1 = 1, thr = 1, thr1 = 1;
  for (int k = 1;; ++k) {
    if (!next_height(wr, c1, rng)) {
      if (k == 1) return std::nullopt;
      Exit e;
      e.wo = wr;
      e.weight = thr;
      e.weight_f1 = thr1;
      e.order = k - 1;
      return e;
    }
    if (k > max_order_) return std::nullopt;
    Vec3 m;
    double w = 1;
    const bool first = k == 1;
    if (!sample_normal(wr, first ? u1 : rng.next(), first ? u2 : rng.next(), rng, m, w))
      return std::nullopt;
    thr *= fresnel_of(fresnel, -wr.dot(m), wavelength_m) * w;
    thr1 *= w;
    wr = reflect(wr, m);
  }
}

void MicrofacetRandomWalk::eval_cos_many(const Vec3& wi, const Vec3* wos, const double* lambda_o,
                                         std::size_t n, WalkRng& rng, const Fresnel* fresnel,
                                         double wavelength_m, double* out, int min_order,
                                         double* energy) const {
  if (!(wi.z() > 0)) return;
  Vec3 wr = -wi;
  double c1 = 1, thr = 1;
  for (int k = 1; k <= max_order_; ++k) {
    if (!next_height(wr, c1, rng)) return;
    if (k >= min_order) {
      const Vec3 v = -wr;
      const double s = sigma(v);
      for (std::size_t j = 0; j < n; ++j) {
        if (!(wos[j].z() > 0)) continue;
        const double p = phase(v, wos[j], fresnel, wavelength_m, s);
        if (p > 0) out[j] += thr * p * std::pow(c1, lambda_o[j]);
      }
    }
    if (k == max_order_) return;
    Vec3 m;
    double w = 1;
    if (!sample_normal(wr, rng.next(), rng.next(), rng, m, w)) return;
    thr *= fresnel_of(fresnel, -wr.dot(m), wavelength_m) * w;
    wr = reflect(wr, m);
    if (!(thr > 0)) return;
    // The energy leaving after this hit: thr times the escape probability G1(wr, h)
    // (a conditional expectation of the exit event, with less variance than counting exits).
    if (energy && k >= min_order && wr.z() > kHorizon) *energy += thr * std::pow(c1, lambda(wr));
  }
}

void MicrofacetRandomWalk::eval_cos_spectral(const Vec3& wi, const Vec3& wo, double lambda_o,
                                             WalkRng& rng, const Fresnel* fresnel,
                                             const double* wavelengths_m, int n, double* out,
                                             int min_order) const {
  if (!(wi.z() > 0) || !(wo.z() > 0) || n < 1) return;
  std::vector<double> thr(static_cast<std::size_t>(n), 1.0);
  Vec3 wr = -wi;
  double c1 = 1;
  for (int k = 1; k <= max_order_; ++k) {
    if (!next_height(wr, c1, rng)) return;
    if (k >= min_order) {
      // phase() with each wavelength's F, the same products in the same order.
      const Vec3 v = -wr;
      const double s = sigma(v);
      const Vec3 hs = v + wo;
      const double len = hs.norm();
      if (len > 0) {
        const Vec3 h = hs / len;
        const double vh = v.dot(h);
        if (h.z() > 0 && vh > 0) {
          const double d = d_->D(h), att = std::pow(c1, lambda_o);
          for (int j = 0; j < n; ++j) {
            const auto u = static_cast<std::size_t>(j);
            const double p = fresnel_of(fresnel, vh, wavelengths_m[j]) * d / (4 * s);
            if (p > 0) out[j] += thr[u] * p * att;
          }
        }
      }
    }
    if (k == max_order_) return;
    Vec3 m;
    double w = 1;
    if (!sample_normal(wr, rng.next(), rng.next(), rng, m, w)) return;
    bool any = false;
    for (int j = 0; j < n; ++j) {
      const auto u = static_cast<std::size_t>(j);
      // A wavelength whose throughput reached 0 adds nothing more (eval_cos_many stops there).
      if (thr[u] > 0) thr[u] *= fresnel_of(fresnel, -wr.dot(m), wavelengths_m[j]) * w;
      if (!(thr[u] > 0)) thr[u] = 0;
      any |= thr[u] > 0;
    }
    wr = reflect(wr, m);
    if (!any) return;
  }
}

double MicrofacetRandomWalk::eval_cos(const Vec3& wi, const Vec3& wo, WalkRng& rng,
                                      const Fresnel* fresnel, double wavelength_m,
                                      int min_order) const {
  if (!(wo.z() > 0)) return 0;
  const double lo = lambda(wo);
  double out = 0;
  eval_cos_many(wi, &wo, &lo, 1, rng, fresnel, wavelength_m, &out, min_order, nullptr);
  return out;
}

}  // namespace microbrdf
