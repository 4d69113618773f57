// Single plus multiple scattering (include/microbrdf/multiple_scattering.hpp,
// MultipleScatteringBrdf).
#include <cstring>
#include <stdexcept>

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

// Distinguishes the streams of eval and sample that share a seed.
constexpr std::uint64_t kSampleSalt = 0x5A3C'96E1'0F2B'7D48ull;

}  // namespace

MultipleScatteringBrdf::MultipleScatteringBrdf(std::shared_ptr<const MicrofacetDistribution> d,
                                               std::shared_ptr<const Fresnel> f,
                                               const MultipleScatteringOptions& opt)
    : single_(d, f, false),
      single_f1_(d, std::make_shared<PerfectMirrorFresnel>(), false),
      f_(std::move(f)),
      walk_(std::move(d), opt.max_order),
      opt_(opt) {
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

std::optional<BrdfSample> MultipleScatteringBrdf::sample(const Vec3& wi, double u1, double u2,
                                                         double wavelength_m) const {
  if (!(wi.z() > 0)) return std::nullopt;
  WalkRng rng(hash_seed(opt_.seed ^ kSampleSalt, {u1, u2, wi.x(), wi.y(), wi.z()}));
  const auto e = walk_.sample(wi, u1, u2, rng, f_.get(), wavelength_m);
  if (!e || !(e->wo.z() > 0)) return std::nullopt;
  BrdfSample s;
  s.wo = e->wo;
  s.pdf = pdf(wi, e->wo);
  if (!(s.pdf > 0)) return std::nullopt;
  s.weight = e->weight;
  return s;
}

double MultipleScatteringBrdf::pdf(const Vec3& wi, const Vec3& wo) const {
  if (!(wi.z() > 0) || !(wo.z() > 0)) return 0;
  return (single_f1_.eval(wi, wo, 0) + table_.eval(wi, wo)) * wo.z();
}

std::string MultipleScatteringBrdf::describe() const {
  return single_.describe() + " + multiple scattering (microfacet random walk, Heitz 2016; " +
         std::to_string(opt_.eval_walks) + " walks per eval)";
}

}  // namespace microbrdf
