// predict: the scattering theory of the run's BRDF (slices, renders, the comparison strip's
// reference), picked from the scans' regime (docs/regime.md) unless the user names one, and what
// that theory needs beyond the input stage: D_K over lambda_q or the scans' mean PSD.
#include <cmath>
#include <optional>
#include <string>

#include "microbrdf/error.hpp"
#include "microbrdf/kirchhoff.hpp"
#include "microbrdf/level.hpp"
#include "microbrdf/psd.hpp"
#include "microbrdf/regime.hpp"
#include "microbrdf/scanset.hpp"
#include "report/predict_stages.hpp"

namespace microbrdf::report {

namespace {

// D_K over lambda_q of every scan, on this rank (the input stage computed it only with
// --kirchhoff).
void compute_kirchhoff(const Context& c, const std::vector<std::string>& paths, NdfSet& ndfs) {
  const KirchhoffOptions ko = dk_options(c.opt);
  KirchhoffAccumulator acc(ko);
  c.log("theory: kirchhoff D_K of " + std::to_string(paths.size()) + " scan(s)");
  auto progress = c.decile_log("theory: kirchhoff D_K");
  for_each_scan(paths, c.opt.read, [&](std::size_t i, const std::string& path, Surface& s) {
    about_file(path, [&] { level_surface(s, c.opt.leveling); });
    KirchhoffOptions k = ko;
    k.progress = [&, i](double f) {
      progress((static_cast<double>(i) + f) / static_cast<double>(paths.size()));
    };
    about_file(path, [&] { acc.merge(KirchhoffAccumulator(k).estimate(s)); });
  });
  take_kirchhoff(acc, ndfs);
}

// The mean PSD of the scans that share the first scan's grid (Rayleigh-Rice needs one PSD; scans
// of another size or spacing are left out, and the log says so).
std::shared_ptr<const AreaPsd> mean_psd(const Context& c, const std::vector<std::string>& paths,
                                        std::size_t& used) {
  std::shared_ptr<AreaPsd> sum;
  double sq2 = 0;
  used = 0;
  // The tile is chosen on the first scan (its correlation lengths) and kept for the others, so
  // that their grids match.
  std::optional<PsdOptions> po;
  for_each_scan(paths, c.opt.read, [&](std::size_t, const std::string& path, Surface& s) {
    about_file(path, [&] { level_surface(s, c.opt.leveling); });
    if (!po) {
      po = about_file(path, [&] { return default_psd_options(s); });
      c.log("theory: PSD: " + po->tile_why);
    }
    AreaPsd p = about_file(path, [&] { return areal_psd(s, *po, path); });
    if (!sum) {
      sum = std::make_shared<AreaPsd>(std::move(p));
      sq2 = sum->sq * sum->sq;
      used = 1;
    } else if (p.nfx == sum->nfx && p.nfy == sum->nfy && p.dfx == sum->dfx && p.dfy == sum->dfy) {
      for (std::size_t k = 0; k < p.value.size(); ++k) sum->value[k] += p.value[k];
      sq2 += p.sq * p.sq;
      sum->tiles += p.tiles;
      ++used;
    } else {
      c.log("theory: " + path + " left out of the mean PSD (another grid than the first scan)");
    }
  });
  if (!sum) throw InputError("no scan gave a PSD for Rayleigh-Rice");
  const double inv = 1.0 / static_cast<double>(used);
  for (double& v : sum->value) v *= inv;
  sum->sq = std::sqrt(sq2 * inv);
  return sum;
}

RegimeVerdict verdict_of(const nlohmann::json& p) {
  RegimeVerdict v;
  v.method = p.at("method").get<std::string>();
  v.none_strictly_valid = p.at("none_strictly_valid").get<bool>();
  return v;
}

}  // namespace

void stage_theory(const Context& c, const std::vector<std::string>& paths, NdfSet& ndfs,
                  nlohmann::json& regime) {
  const auto& o = c.opt;
  // What was asked: --render-ndf kirchhoff names the Kirchhoff theory.
  const std::string requested =
      o.render_ndf == "kirchhoff" && o.theory == "auto" ? "kirchhoff" : o.theory;
  std::string chosen = requested, why;
  if (requested == "auto") {
    if (regime.is_object()) {
      // The theory of normal incidence when it holds at every incidence of the run; else
      // Kirchhoff where it does (a rough surface whose grazing slices keep a specular part).
      const auto& per = regime.at("per_incidence");
      const auto& p0 = per.at(0);
      auto everywhere = [&](const std::string& m) {
        for (const auto& p : per)
          if (!regime_allows(verdict_of(p), m)) return false;
        return true;
      };
      chosen = p0.at("method").get<std::string>();
      why = "auto: the regime at normal incidence and " +
            std::to_string(std::lround(o.wavelength_m * 1e9)) +
            " nm: " + p0.at("reason").get<std::string>();
      if (!everywhere(chosen) && everywhere("kirchhoff")) {
        for (const auto& p : per)
          if (!regime_allows(verdict_of(p), chosen)) {
            why = "auto: kirchhoff holds at every incidence of the run, " + chosen +
                  " not at theta_i " +
                  std::to_string(std::lround(p.at("theta_i_deg").get<double>())) +
                  " deg: " + p.at("reason").get<std::string>();
            break;
          }
        chosen = "kirchhoff";
      }
    } else {
      chosen = "geometric";
      why = "auto: no scan statistics to decide from; geometric optics";
    }
  } else {
    // In words that read the same from the CLI (--theory) and Python (theory=).
    why = "asked for (" +
          std::string(o.render_ndf == "kirchhoff" && o.theory == "auto" ? "render NDF kirchhoff"
                                                                        : "theory " + o.theory) +
          ")";
  }
  ndfs.theory = chosen;
  ndfs.render = chosen == "kirchhoff"         ? "kirchhoff"
                : o.render_ndf == "kirchhoff" ? "filtered"
                                              : o.render_ndf;
  nlohmann::json rec = {{"requested", requested}, {"chosen", chosen}, {"why", why}};
  c.log("theory: " + chosen + " (" + why + ")");
  if (chosen == "kirchhoff" && !ndfs.kirchhoff) compute_kirchhoff(c, paths, ndfs);
  if (chosen == "rayleigh-rice") {
    std::size_t used = 0;
    ndfs.psd = mean_psd(c, paths, used);
    rec["psd_scans"] = used;
    rec["psd_sq_m"] = ndfs.psd->sq;
    rec["psd_rms_slope"] = ndfs.psd->rms_slope();
    rec["psd_tiles"] = ndfs.psd->tiles;
    rec["psd_tile_samples"] = ndfs.psd->tile_nx;
    rec["psd_tile_choice"] = ndfs.psd->tile_why;
  }
  if (!regime.is_object()) return;
  regime["theory"] = rec;
  regime["used"] = chosen;
  std::string outside;
  for (auto& p : regime.at("per_incidence")) {
    const bool ok = regime_allows(verdict_of(p), chosen);
    p["used_is_valid"] = ok;
    if (!ok && outside.empty())
      outside = p.at("reason").get<std::string>() + " at theta_i " +
                std::to_string(std::lround(p.at("theta_i_deg").get<double>())) + " deg";
  }
  if (outside.empty()) return;
  // A forced theory outside its validity, or auto's pick (made at normal incidence) failing at a
  // slice's incidence.
  const std::string label = chosen == "geometric" ? "geometric (" + ndfs.render + " NDF)" : chosen;
  c.warn(
      "method_outside_validity",
      "the BRDF slices and renders use " + label + " scattering, outside its validity: " + outside,
      requested == "auto"
          ? "the theory was picked at normal incidence; read the slices at this incidence "
            "with care (docs/regime.md)"
          : "leave --theory at auto for the valid theory, or see docs/regime.md");
}

}  // namespace microbrdf::report
