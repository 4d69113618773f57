// BRDF helpers and the microfacet BRDF (include/microbrdf/brdf.hpp).
#include "microbrdf/brdf.hpp"

#include <cmath>
#include <stdexcept>

namespace microbrdf {
namespace {
constexpr double kPi = 3.14159265358979323846;
}

MicrofacetBrdf::MicrofacetBrdf(std::shared_ptr<const MicrofacetDistribution> d,
                               std::shared_ptr<const Fresnel> f, bool separable_g)
    : d_(std::move(d)), f_(std::move(f)), separable_(separable_g) {
  if (!d_ || !f_)
    throw std::invalid_argument("MicrofacetBrdf needs a distribution and a Fresnel term");
}

double MicrofacetBrdf::eval(const Vec3& wi, const Vec3& wo, double wavelength_m) const {
  if (wi.z() <= 0 || wo.z() <= 0) return 0;
  const Vec3 hs = wi + wo;
  const double len = hs.norm();
  if (len == 0) return 0;
  const Vec3 h = hs / len;
  const double g = d_->G2(wi, wo, h, separable_);
  if (g == 0) return 0;
  return f_->eval(wi.dot(h), wavelength_m) * d_->D(h) * g / (4 * wi.z() * wo.z());
}

std::optional<BrdfSample> MicrofacetBrdf::sample(const Vec3& wi, double u1, double u2,
                                                 double wavelength_m) const {
  if (wi.z() <= 0) return std::nullopt;
  const Vec3 m = d_->sample_visible(wi, u1, u2);
  const double im = wi.dot(m);
  if (im <= 0) return std::nullopt;
  const Vec3 wo = 2 * im * m - wi;
  if (wo.z() <= 0) return std::nullopt;
  BrdfSample s;
  s.wo = wo;
  const double q = d_->sampling_pdf(wi, m);  // density of m per steradian
  s.pdf = q / (4 * im);
  if (!(s.pdf > 0)) return std::nullopt;
  // f cos / pdf = F D G2 / (4 wi.z) * 4 (wi.m) / q. With visible normals, q = (wi.m) D /
  // sigma+(wi) and this is F G2 sigma+(wi) / wi.z.
  const double g = d_->G2(wi, wo, m, separable_);
  s.weight = f_->eval(im, wavelength_m) * g * d_->D(m) * im / (wi.z() * q);
  return s;
}

std::optional<HalfVector> reflection_half_vector(const Vec3& wi, const Vec3& wo) {
  if (wi.z() <= 0 || wo.z() <= 0) return std::nullopt;
  const Vec3 hs = wi + wo;
  const double len = hs.norm();
  if (len == 0) return std::nullopt;
  const Vec3 h = hs / len;
  const double ih = wi.dot(h);
  if (ih <= 0) return std::nullopt;
  return HalfVector{h, ih};
}

double MicrofacetBrdf::pdf(const Vec3& wi, const Vec3& wo) const {
  const auto hv = reflection_half_vector(wi, wo);
  return hv ? d_->sampling_pdf(wi, hv->h) / (4 * hv->wi_dot_h) : 0.0;
}

std::string MicrofacetBrdf::describe() const {
  return "microfacet (Dong eq. 1): " + d_->describe() + ", " + f_->describe() +
         (separable_ ? ", separable Smith G1 G1" : ", height-correlated Smith G2");
}

void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& w) {
  x.assign(static_cast<std::size_t>(n), 0);
  w.assign(static_cast<std::size_t>(n), 0);
  for (int i = 0; i < (n + 1) / 2; ++i) {
    double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), pp = 0;
    for (int it = 0; it < 100; ++it) {
      double p1 = 1, p2 = 0;
      for (int j = 1; j <= n; ++j) {
        const double p3 = p2;
        p2 = p1;
        p1 = ((2.0 * j - 1) * z * p2 - (j - 1.0) * p3) / j;
      }
      pp = n * (z * p1 - p2) / (z * z - 1);
      const double dz = p1 / pp;
      z -= dz;
      if (std::abs(dz) < 1e-15) break;
    }
    const auto a = static_cast<std::size_t>(i), b = static_cast<std::size_t>(n - 1 - i);
    x[a] = -z;
    x[b] = z;
    w[a] = w[b] = 2 / ((1 - z * z) * pp * pp);
  }
}

double directional_albedo(const Brdf& brdf, const Vec3& wi, double wavelength_m, int n_theta,
                          int n_phi) {
  std::vector<double> x, w;
  gauss_legendre(n_theta, x, w);
  double sum = 0;
  for (int i = 0; i < n_theta; ++i) {
    const double mu = 0.5 * (x[static_cast<std::size_t>(i)] + 1);  // cos theta_o in (0, 1)
    const double st = std::sqrt(std::max(0.0, 1 - mu * mu));
    double ring = 0;
    for (int j = 0; j < n_phi; ++j) {
      const double phi = 2 * kPi * (j + 0.5) / n_phi;
      ring += brdf.eval(wi, Vec3(st * std::cos(phi), st * std::sin(phi), mu), wavelength_m);
    }
    sum += 0.5 * w[static_cast<std::size_t>(i)] * mu * ring * (2 * kPi / n_phi);
  }
  return sum;
}

double directional_albedo_sampled(const Brdf& brdf, const Vec3& wi, double wavelength_m, int n) {
  double sum = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      auto s = brdf.sample(wi, (i + 0.5) / n, (j + 0.5) / n, wavelength_m);
      if (s) sum += s->weight;
    }
  return sum / (static_cast<double>(n) * n);
}

BrdfSlice tabulate_slice(const Brdf& brdf, double theta_i, double wavelength_m, SlicePlane plane,
                         std::size_t samples) {
  if (samples < 2) samples = 2;
  const Vec3 wi(-std::sin(theta_i), 0, std::cos(theta_i));
  const Vec3 r(std::sin(theta_i), 0, std::cos(theta_i));
  BrdfSlice s;
  const double lim = kPi / 2 - 1e-9;
  for (std::size_t k = 0; k < samples; ++k) {
    const double t = -lim + 2 * lim * static_cast<double>(k) / static_cast<double>(samples - 1);
    const Vec3 wo = plane == SlicePlane::in ? Vec3(std::sin(t), 0, std::cos(t))
                                            : Vec3(std::cos(t) * r + std::sin(t) * Vec3(0, 1, 0));
    s.angle_deg.push_back(t * 180 / kPi);
    s.value.push_back(brdf.eval(wi, wo, wavelength_m));
    s.wo.push_back(wo);
  }
  return s;
}

}  // namespace microbrdf
