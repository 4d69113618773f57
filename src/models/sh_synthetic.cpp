// sh_estimate_by_sampling: the estimator fed by exits drawn from a known BRDF (no geometry), the
// reference experiment for W92's estimator and its convergence measure Q (docs/theory.md §6.4-6.5).
#include <cmath>
#include <random>
#include <vector>

#include "microbrdf/error.hpp"
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

}  // namespace microbrdf
