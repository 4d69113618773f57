// Single plus multiple scattering (include/microbrdf/multiple_scattering.hpp,
// MultipleScatteringBrdf).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "core/splitmix64.hpp"
#include "microbrdf/multiple_scattering.hpp"

namespace microbrdf {
namespace {

std::uint64_t bits(double x) {
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

// A stream seed from the exact bits of the arguments: the same call, the same numbers.
std::uint64_t hash_seed(std::uint64_t seed, std::initializer_list<double> xs) {
  std::uint64_t h = detail::splitmix64(seed);
  for (const double x : xs) h = detail::splitmix64(h ^ bits(x));
  return h;
}

constexpr double kPi = 3.14159265358979323846;

}  // namespace

MultipleScatteringBrdf::MultipleScatteringBrdf(std::shared_ptr<const MicrofacetDistribution> d,
                                               std::shared_ptr<const Fresnel> f,
                                               const MultipleScatteringOptions& opt)
    : single_(d, f, false), f_(std::move(f)), walk_(std::move(d), opt.max_order), opt_(opt) {
  if (opt_.eval_walks < 1)
    throw std::invalid_argument("MultipleScatteringBrdf: eval_walks must be >= 1");
  MsTableOptions t = opt_.table;
  t.seed = opt_.seed;
  table_ = tabulate_multiple_scattering(walk_, nullptr, 550e-9, t);
}

double MultipleScatteringBrdf::eval_single(const Vec3& wi, const Vec3& wo,
                                           double wavelength_m) const {
  return single_.eval(wi, wo, wavelength_m);
}

double MultipleScatteringBrdf::eval_multiple(const Vec3& wi, const Vec3& wo, double wavelength_m,
                                             int walks) const {
  if (!(wi.z() > 0) || !(wo.z() > 0) || walks < 1) return 0;
  // The wavelength is not in the seed: the same walks at every wavelength keep a spectrum smooth.
  WalkRng rng(hash_seed(opt_.seed, {wi.x(), wi.y(), wi.z(), wo.x(), wo.y(), wo.z()}));
  const double lo = walk_.lambda(wo);
  double sum = 0;
  for (int k = 0; k < walks; ++k)
    walk_.eval_cos_many(wi, &wo, &lo, 1, rng, f_.get(), wavelength_m, &sum, 2, nullptr);
  return sum / (walks * wo.z());
}

double MultipleScatteringBrdf::eval(const Vec3& wi, const Vec3& wo, double wavelength_m) const {
  if (!(wi.z() > 0) || !(wo.z() > 0)) return 0;
  return single_.eval(wi, wo, wavelength_m) + eval_multiple(wi, wo, wavelength_m, opt_.eval_walks);
}

void MultipleScatteringBrdf::eval_spectral(const Vec3& wi, const Vec3& wo,
                                           const double* wavelengths_m, int n, double* f) const {
  for (int k = 0; k < n; ++k) f[k] = 0;
  if (!(wi.z() > 0) || !(wo.z() > 0) || n < 1) return;
  // eval_multiple's walks (the seed does not see the wavelength), once for all wavelengths.
  std::vector<double> sum(static_cast<std::size_t>(n), 0.0);
  WalkRng rng(hash_seed(opt_.seed, {wi.x(), wi.y(), wi.z(), wo.x(), wo.y(), wo.z()}));
  const double lo = walk_.lambda(wo);
  for (int w = 0; w < opt_.eval_walks; ++w)
    walk_.eval_cos_spectral(wi, wo, lo, rng, f_.get(), wavelengths_m, n, sum.data(), 2);
  for (int k = 0; k < n; ++k)
    f[k] = single_.eval(wi, wo, wavelengths_m[k]) +
           sum[static_cast<std::size_t>(k)] / (opt_.eval_walks * wo.z());
}

double MultipleScatteringBrdf::cosine_share(const Vec3& wi) const {
  // The energy of orders >= 2 on a white surface, kept inside [0.02, 0.9]: the cosine lobe must
  // cover the multiple-scattering lobe wherever it is not 0, and the single lobe stays sampled.
  return std::clamp(table_.energy(wi), 0.02, 0.9);
}

std::optional<BrdfSample> MultipleScatteringBrdf::sample(const Vec3& wi, double u1, double u2,
                                                         double wavelength_m) const {
  if (!(wi.z() > 0)) return std::nullopt;
  const double c = cosine_share(wi);
  Vec3 wo;
  if (u1 < c) {  // the cosine lobe
    const double r = std::sqrt(u1 / c), p = 2 * kPi * u2;
    wo = Vec3(r * std::cos(p), r * std::sin(p), std::sqrt(std::max(0.0, 1 - r * r)));
  } else {  // the single-scattering lobe (visible normals of wi, reflected)
    const Vec3 m = single_.distribution().sample_visible(wi, (u1 - c) / (1 - c), u2);
    const double im = wi.dot(m);
    if (!(im > 0)) return std::nullopt;
    wo = 2 * im * m - wi;
  }
  if (!(wo.z() > 0)) return std::nullopt;
  BrdfSample s;
  s.wo = wo;
  s.pdf = pdf(wi, wo);
  if (!(s.pdf > 0)) return std::nullopt;
  s.weight = eval(wi, wo, wavelength_m) * wo.z() / s.pdf;
  return s;
}

double MultipleScatteringBrdf::pdf(const Vec3& wi, const Vec3& wo) const {
  if (!(wi.z() > 0) || !(wo.z() > 0)) return 0;
  const double c = cosine_share(wi);
  return (1 - c) * single_.pdf(wi, wo) + c * wo.z() / kPi;
}

std::string MultipleScatteringBrdf::describe() const {
  return single_.describe() + " + multiple scattering (microfacet random walk, Heitz 2016; " +
         std::to_string(opt_.eval_walks) + " walks per eval)";
}

}  // namespace microbrdf
