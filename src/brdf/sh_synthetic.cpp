// sh_estimate_by_sampling: the estimator fed by exits drawn from a known BRDF (no geometry), the
// reference experiment for W92's estimator and its convergence measure Q (docs/theory.md §6.4-6.5).
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "core/splitmix64.hpp"
#include "microbrdf/brdf.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/sh_basis.hpp"
#include "microbrdf/sh_brdf.hpp"

namespace microbrdf {

void sh_estimate_by_sampling(ShEstimator& e, const Brdf& brdf, std::size_t n_incident, int rays,
                             std::uint64_t seed, double wavelength_m) {
  if (rays < 1) throw InputError("sh_estimate_by_sampling: rays per direction must be >= 1");
  constexpr double kPi = 3.14159265358979323846;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const int n = e.basis().size();
  std::vector<double> y(n), sum(n);
  for (std::size_t i = 0; i < n_incident; ++i) {
    const double u1 = u(rng), u2 = u(rng), r = std::sqrt(u1), p = 2 * kPi * u2;
    const Vec3 wi(r * std::cos(p), r * std::sin(p), std::sqrt(std::max(0.0, 1 - u1)));
    std::fill(sum.begin(), sum.end(), 0.0);
    double energy = 0;
    for (int k = 0; k < rays; ++k) {
      auto s = brdf.sample(wi, u(rng), u(rng), wavelength_m);
      if (!s || !(s->weight > 0) || !(s->wo.z() > 0)) continue;  // absorbed: still counted
      e.basis().eval(s->wo, y.data());
      for (int j = 0; j < n; ++j) sum[j] += s->weight * y[j];
      energy += s->weight;
    }
    e.add_incident(wi, wi.z() / kPi, sum.data(), static_cast<std::size_t>(rays), energy);
  }
}

ShEstimator sh_estimate_chunked(const Brdf& brdf, int lmax, std::size_t n_incident, int rays,
                                std::uint64_t seed, double wavelength_m,
                                const std::function<void(std::size_t, std::size_t)>& progress) {
  if (n_incident < 1 || rays < 1)
    throw InputError("the SH estimate needs at least one incident direction and one ray");
  const int chunks = static_cast<int>(std::min<std::size_t>(kShEstimateChunks, n_incident));
  std::vector<ShEstimator> part(static_cast<std::size_t>(chunks), ShEstimator(lmax));
  std::size_t done = 0;
#pragma omp parallel for schedule(dynamic, 1)
  for (int c = 0; c < chunks; ++c) {
    const auto uc = static_cast<std::size_t>(c);
    const std::size_t n = n_incident / chunks + (uc < n_incident % chunks);
    sh_estimate_by_sampling(part[uc], brdf, n, rays, detail::chunk_seed(seed, uc), wavelength_m);
#pragma omp critical
    if (progress) progress(done++, static_cast<std::size_t>(chunks));
  }
  for (std::size_t c = 1; c < part.size(); ++c) part[0].merge(part[c]);
  return part[0];
}

}  // namespace microbrdf
