// predict: the energy single scattering loses on the measured NDF (white furnace, F = 1), per
// incidence along the table's two axes, from microfacet random walks on the NDF itself
// (multiple_scattering.hpp, Heitz et al. 2016; docs/multiple_scattering.md), and whether the
// comparison strip shows the multiple-scattering BRDF beside the single.
#include "report/predict_multiple_scattering.hpp"

#include <cmath>
#include <sstream>

#include "core/splitmix64.hpp"
#include "microbrdf/multiple_scattering.hpp"
#include "microbrdf/tabulated_distribution.hpp"
#include "report/html.hpp"

namespace microbrdf::report {

namespace {
constexpr std::size_t kWalks = 4000;  // per incidence: standard error <= 0.008 of the energy
constexpr double kThetaDeg[] = {0, 20, 40, 60, 70, 80};
constexpr double kShownAbove = 0.02;  // auto: the strip gains the MS render above this loss
constexpr double kUpToDeg = 70;       // ... at an incidence up to this
}  // namespace

std::string ms_table_name(const NdfSet& ndfs) {
  return ndfs.render == "naive" && ndfs.naive ? "naive" : "filtered";
}

const TabulatedNdf& ms_table_of(const NdfSet& ndfs) {
  return ms_table_name(ndfs) == "naive" ? *ndfs.naive : *ndfs.filtered;
}

nlohmann::json stage_energy_loss(const Context& c, const NdfSet& ndfs) {
  const TabulatedNdf& table = ms_table_of(ndfs);
  const std::string name = ms_table_name(ndfs);
  const MicrofacetRandomWalk walk(std::make_shared<TabulatedDistribution>(table));
  nlohmann::json per = nlohmann::json::array();
  double worst = 0, worst_theta = 0, worst_phi = 0;
  std::uint64_t stream = 0;
  for (double phi_deg : {0.0, 90.0})
    for (double theta_deg : kThetaDeg) {
      const double t = theta_deg * M_PI / 180, p = phi_deg * M_PI / 180;
      const Vec3 wi(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
      // One fixed stream per incidence: the same numbers on any thread or rank count.
      WalkRng rng(detail::splitmix64(detail::chunk_seed(c.opt.seed, stream++)));
      double single = 0, multiple = 0, dropped = 0, m2 = 0;
      for (std::size_t k = 0; k < kWalks; ++k) {
        const double u1 = rng.next(), u2 = rng.next();
        // No Fresnel (nullptr: F = 1), so the wavelength is not used: the run's own is passed.
        const auto e = walk.sample(wi, u1, u2, rng, nullptr, c.opt.wavelength_m);
        if (!e) {
          dropped += 1;
          continue;
        }
        if (e->order >= 2) {
          multiple += e->weight_f1;
          m2 += e->weight_f1 * e->weight_f1;
        } else {
          single += e->weight_f1;
        }
      }
      const double n = static_cast<double>(kWalks);
      const double lost = multiple / n;
      const double se = std::sqrt(std::max(0.0, m2 / n - lost * lost) / n);
      per.push_back({{"theta_i_deg", theta_deg},
                     {"phi_i_deg", phi_deg},
                     {"single_albedo_f1", single / n},
                     {"energy_lost_f1", lost},
                     {"standard_error", se},
                     {"dropped_fraction", dropped / n}});
      if (theta_deg <= kUpToDeg && lost > worst) {
        worst = lost;
        worst_theta = theta_deg;
        worst_phi = phi_deg;
      }
    }
  const std::string mode = c.opt.multiple_scattering;
  const bool shown = mode == "on" || (mode == "auto" && worst > kShownAbove);
  std::ostringstream why;
  why << "single scattering loses " << num(100 * worst, 3) << " % of the light of a white (F = 1) "
      << "surface at theta_i " << worst_theta << " deg, phi_i " << worst_phi
      << " deg (the most up to " << kUpToDeg << " deg); ";
  if (mode == "auto")
    why << (shown ? "above " : "not above ") << 100 * kShownAbove << " %, so the comparison strip "
        << (shown ? "shows" : "does not show") << " the multiple-scattering BRDF";
  else
    why << "--multiple-scattering " << mode;
  c.log("multiple scattering: " + why.str());
  return {{"ndf", name},
          {"method", "microfacet random walk on the tabulated NDF (Heitz et al. 2016), " +
                         std::to_string(kWalks) + " walks per incidence, F = 1"},
          {"per_incidence", per},
          {"max_energy_lost_f1", worst},
          {"max_at_theta_i_deg", worst_theta},
          {"max_at_phi_i_deg", worst_phi},
          {"in_comparison_strip", shown},
          {"why", why.str()}};
}

std::string energy_loss_html(const nlohmann::json& s) {
  if (!s.contains("multiple_scattering") || !s["multiple_scattering"].is_object()) return "";
  const auto& m = s["multiple_scattering"];
  std::ostringstream p;
  p << "<h3 id=\"ms\">Energy single scattering loses</h3>\n<p>On the " << escape(m.value("ndf", ""))
    << " NDF, with a white material (F = 1): the share of the light that leaves after two or "
       "more bounces between microfacets, which a single-scattering BRDF (every fit, the "
       "measured NDF's BRDF) drops. "
    << escape(m.value("why", "")) << ". Method: " << escape(m.value("method", ""))
    << " (docs/multiple_scattering.md).</p>\n<table>\n<tr><th>theta_i</th><th>lost, light "
       "along x (phi_i 0)</th><th>lost, light along y (phi_i 90 deg)</th></tr>\n";
  const auto& per = m["per_incidence"];
  const std::size_t half = per.size() / 2;
  for (std::size_t i = 0; i < half; ++i) {
    auto cell = [&](const nlohmann::json& q) {
      return num(100 * q.value("energy_lost_f1", 0.0), 3) + " % &plusmn; " +
             num(100 * q.value("standard_error", 0.0), 2) + " %";
    };
    p << "<tr><td class=\"n\">" << num(per[i].value("theta_i_deg", 0.0))
      << " deg</td><td class=\"n\">" << cell(per[i]) << "</td><td class=\"n\">"
      << cell(per[i + half]) << "</td></tr>\n";
  }
  p << "</table>\n";
  return p.str();
}

}  // namespace microbrdf::report
