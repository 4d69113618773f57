// predict stages 3-4: parametric fits of the filtered NDF, NDF cuts (measured vs fitted) and
// BRDF slices / directional albedos of the measured, fitted and Kirchhoff models.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "microbrdf/brdf.hpp"
#include "microbrdf/brdf_albedo.hpp"
#include "microbrdf/brdf_slice.hpp"
#include "microbrdf/kirchhoff_brdf.hpp"
#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/multiple_scattering.hpp"
#include "microbrdf/ndf_model.hpp"
#include "microbrdf/plot.hpp"
#include "microbrdf/rayleigh_rice.hpp"
#include "microbrdf/tabulated_distribution.hpp"
#include "microbrdf/units.hpp"
#include "report/predict_multiple_scattering.hpp"
#include "report/predict_stages.hpp"

namespace microbrdf::report {
namespace {

constexpr double kDeg = 180.0 / M_PI;

nlohmann::json finite_array(const std::vector<double>& v) {
  // nlohmann writes NaN as null; the slices never hold one, but keep the JSON strict anyway.
  nlohmann::json a = nlohmann::json::array();
  for (double x : v) a.push_back(std::isfinite(x) ? x : 0.0);
  return a;
}

/// f along the cut of tabulate_slice (brdf_slice.hpp) at the given signed angles (deg).
std::vector<double> slice_values(const Brdf& b, double ti, double lambda, SlicePlane plane,
                                 const std::vector<double>& angles_deg) {
  const Vec3 wi = slice_light(ti);
  std::vector<double> v;
  for (double a : angles_deg) {
    const Vec3 wo = slice_view(ti, a / kDeg, plane);
    v.push_back(wo.z() > 1e-9 ? b.eval(wi, wo, lambda) : 0.0);
  }
  return v;
}

// n angles (deg) evenly from lo to hi; a rounding residue at 0 becomes 0 (the mirror direction,
// not -7e-15 deg).
std::vector<double> even_angles(double lo, double hi, std::size_t n) {
  std::vector<double> a(n);
  for (std::size_t i = 0; i < n; ++i) {
    a[i] = lo + (hi - lo) * static_cast<double>(i) / static_cast<double>(n - 1);
    if (std::abs(a[i]) < 1e-9) a[i] = 0;
  }
  return a;
}

// A slice plot's frame: log BRDF axis over [lo, hi] deg; when top > 0 the y range is
// [top * floor, top * 3].
Plot slice_frame(const std::string& title, const std::string& x_label, double lo, double hi,
                 double top, double floor) {
  Plot p;
  p.title = title;
  p.x.label = x_label;
  p.y.label = "BRDF (1/sr)";
  p.y.scale = AxisScale::Log;
  p.x.min = lo;
  p.x.max = hi;
  if (top > 0) {
    p.y.min = top * floor;
    p.y.max = top * 3;
  }
  return p;
}

constexpr double kPoorFit = 0.45;  // relative L2 error from which a fit is called poor
// Below both, a fit is good (docs/report.md, "Fit verdicts").
constexpr double kGoodFitL2 = 0.2, kGoodFitHellinger = 0.1;

// good: converged, relative L2 error < 0.2 and Hellinger distance < 0.1 to the table;
// usable: converged and relative L2 error < 0.45; poor: anything else (the fit_poor warning and
// a fit at a bound say why).
std::string fit_verdict(const FitResult& r) {
  if (!r.converged || !r.at_bound.empty() || !(r.relative_l2_error < kPoorFit)) return "poor";
  if (r.relative_l2_error < kGoodFitL2 && r.hellinger < kGoodFitHellinger) return "good";
  return "usable";
}

void warn_fit(const Context& c, const FitResult& r, bool zoomed) {
  const std::string& m = r.model;
  if (!r.at_bound.empty()) {
    const bool floor = r.at_bound.find("lower alpha") != std::string::npos;
    c.warn("fit_at_bound",
           "the " + m + " fit ended at " + r.at_bound +
               ": not converged, the parameter is the bound, not the surface's value",
           floor && zoomed
               ? "the lobe is narrower than the fits' smallest width even on the zoomed table: "
                 "take the widths from the rms slopes of the zoomed filtered NDF (alpha = "
                 "sqrt(2) x rms slope, summary.json ndf.filtered.zoom)"
           : floor ? "the lobe is narrower than the table resolves: raise --resolution (see the "
                     "table warning) and meanwhile take the widths from the rms slopes of the "
                     "filtered NDF (alpha = sqrt(2) x rms slope, summary.json ndf.filtered)"
                   : "the model does not suit this NDF: look at the NDF preview and the cuts, and "
                     "prefer a model whose fit converged or the measured table itself");
  }
  if (r.relative_l2_error >= kPoorFit) {
    char b[160];
    std::snprintf(b, sizeof b,
                  "the %s fit departs from the filtered NDF by a relative L2 error of %.3g "
                  "(Hellinger distance %.3g)",
                  m.c_str(), r.relative_l2_error, r.hellinger);
    c.warn("fit_poor", b,
           "do not use this model's parameters for this surface: compare the other fits (the "
           "lowest Hellinger distance) or render with the measured NDF table "
           "(ndf_filtered.npy)");
  }
}

constexpr double kWidthVsRms = 0.05;  // Beckmann width vs the NDF's rms slope, relative

// Kurtosis E[(s - mean)^4] / E[(s - mean)^2]^2 of the slope s = -(m_x, m_y)/m_z . u under the
// table (3 for Gaussian slopes, as Beckmann's).
double slope_kurtosis(const TabulatedNdf& t, double phi) {
  const double ux = std::cos(phi), uy = std::sin(phi);
  double w = 0, m1 = 0;
  auto each = [&](auto&& f) {
    for (std::size_t iy = 0; iy < t.resolution(); ++iy)
      for (std::size_t ix = 0; ix < t.resolution(); ++ix) {
        const double v = t.at(ix, iy), x = t.node_x(ix), y = t.node_y(iy), r2 = x * x + y * y;
        if (!(v > 0) || r2 >= 1) continue;
        const double z = std::sqrt(1 - r2);
        f(v, -(x * ux + y * uy) / z);
      }
  };
  each([&](double v, double sl) {
    w += v;
    m1 += v * sl;
  });
  if (!(w > 0)) return 3;
  m1 /= w;
  double m2 = 0, m4 = 0;
  each([&](double v, double sl) {
    const double d = (sl - m1) * (sl - m1);
    m2 += v * d;
    m4 += v * d * d;
  });
  return m2 > 0 ? (m4 / w) / ((m2 / w) * (m2 / w)) : 3;
}

// A heavy-tailed model (one with a tail exponent, e.g. Student-t) "fixes" the Beckmann fit's
// width problem when its own fit converged and lowers the Hellinger distance by at least 30 %.
constexpr double kHeavyTailGain = 0.3;

const FitResult* heavy_tail_fit(const FitResult& beckmann, const std::vector<FitResult>& fits) {
  const FitResult* best = nullptr;
  for (const auto& f : fits) {
    const NdfModel& m = ndf_model(f.model);
    if (!m.has_kind(NdfParam::Kind::Exponent) || !f.converged) continue;
    if (!(f.hellinger <= (1 - kHeavyTailGain) * beckmann.hellinger)) continue;
    if (!best || f.hellinger < best->hellinger) best = &f;
  }
  return best;
}

// The sentence the width warning ends with when a heavy-tailed fit fixes it.
std::string heavy_tail_sentence(const FitResult& beckmann, const FitResult* best) {
  if (!best) return "";
  const NdfModel& m = ndf_model(best->model);
  std::string tail;
  for (std::size_t i = 0; i < best->params.size(); ++i)
    if (m.params()[i].kind == NdfParam::Kind::Exponent) {
      char b[64];
      std::snprintf(b, sizeof b, "%s%s %.3g", tail.empty() ? "" : ", ",
                    best->params.names[i].c_str(), best->params.values[i]);
      tail += b;
    }
  char b[320];
  std::snprintf(b, sizeof b,
                "; the heavy-tailed %s fit (%s) holds the core and the tails at once: Hellinger "
                "distance %.3g against the Beckmann fit's %.3g",
                best->model.c_str(), tail.c_str(), best->hellinger, beckmann.hellinger);
  return b;
}

// The Beckmann fit's widths against the table's own rms slopes along the fitted axes (alpha =
// sqrt 2 x rms slope for Beckmann): a departure above kWidthVsRms warns and says why (the slopes
// are not Gaussian: a narrow core with heavy tails, or the reverse).
// The warning names the heavy-tailed fit that fixes it, if one does.
void warn_width_vs_rms(const Context& c, const FitResult& r, const TabulatedNdf& t,
                       const std::string& where, nlohmann::json& j,
                       const std::vector<FitResult>& fits) {
  if (r.model != "beckmann" || !r.at_bound.empty()) return;  // (a bound fit warns)
  const double ax = r.params.at("alpha_x") / std::sqrt(2.0),
               ay = r.params.at("alpha_y") / std::sqrt(2.0);
  const double sx = t.rms_slope(r.phi), sy = t.rms_slope(r.phi + M_PI / 2);
  const double dx = sx > 0 ? ax / sx - 1 : 0, dy = sy > 0 ? ay / sy - 1 : 0;
  const double kx = slope_kurtosis(t, r.phi), ky = slope_kurtosis(t, r.phi + M_PI / 2);
  j["width_vs_rms"] = {{"rms_slope_fit", {ax, ay}},
                       {"rms_slope_table", {sx, sy}},
                       {"relative_difference", {dx, dy}},
                       {"slope_kurtosis", {kx, ky}}};
  if (!(std::max(std::abs(dx), std::abs(dy)) > kWidthVsRms)) return;
  const FitResult* fixer = heavy_tail_fit(r, fits);
  const std::string fix = heavy_tail_sentence(r, fixer);
  j["width_vs_rms"]["fixed_by"] = fixer ? nlohmann::json(fixer->model) : nlohmann::json(nullptr);
  char b[420];
  std::snprintf(b, sizeof b,
                "the Beckmann fit's widths correspond to rms slopes %.3g x %.3g (alpha / sqrt 2), "
                "but the fitted NDF's own rms slopes along the same axes are %.3g x %.3g "
                "(%+.0f%%, %+.0f%%): its slopes are not Gaussian (kurtosis %.3g and %.3g; "
                "Gaussian 3), %s",
                ax, ay, sx, sy, 100 * dx, 100 * dy, kx, ky,
                std::max(kx, ky) > 3 ? "a narrow core with heavy tails: the fit follows the core, "
                                       "the rms slopes weigh the tails"
                                     : "a flat-topped lobe with light tails: the fit widens to "
                                       "the shoulders, the rms slopes stay narrower");
  c.warn("fit_width_vs_rms", std::string(b) + fix,
         "use the fitted widths for the highlight's shape and the rms slopes (summary.json " +
             where +
             ") for the overall spread; GGX and ellipsoid have no finite rms slope, compare "
             "them with the NDF cuts instead");
}

}  // namespace

nlohmann::json stage_fits(const Context& c, const NdfSet& ndfs, std::vector<FitResult>& fits,
                          nlohmann::json& timing) {
  nlohmann::json out = nlohmann::json::array();
  // Every registered model, in registration order; ranked by Hellinger distance below.
  for (const NdfModel* model : ndf_models()) {
    const std::string m = model->name();
    // A zoomed table when the whole-disk one does not resolve the lobe (stage_zoom).
    const TabulatedNdf& table = ndfs.filtered_zoom ? *ndfs.filtered_zoom : *ndfs.filtered;
    c.log("fits: " + m + " to the filtered NDF" + (ndfs.filtered_zoom ? " (zoomed table)" : ""));
    FitOptions fo;
    fo.model = m;
    fo.threads = c.opt.threads;
    FitResult r = fit_ndf(table, fo);
    nlohmann::json j = fit_result_json(r);
    j.erase("seconds");  // wall time lives under "timing" only (determinism)
    timing["fit_" + m + "_s"] = r.seconds;
    j["source"] = ndfs.filtered_zoom ? "filtered_zoom" : "filtered";
    j["verdict"] = fit_verdict(r);
    if (m == "ellipsoid") {
      write_fit_report(table, r, c.path("fit_ellipsoid"));
      j["compare_image"] = "fit_ellipsoid/compare.png";
    }
    warn_fit(c, r, ndfs.filtered_zoom != nullptr);
    out.push_back(std::move(j));
    fits.push_back(r);
  }
  // (After all fits: the width warning names a heavy-tailed model that fixes it.)
  const TabulatedNdf& table = ndfs.filtered_zoom ? *ndfs.filtered_zoom : *ndfs.filtered;
  for (std::size_t i = 0; i < fits.size(); ++i)
    warn_width_vs_rms(c, fits[i], table, ndfs.filtered_zoom ? "ndf.filtered.zoom" : "ndf.filtered",
                      out[i], fits);
  // Rank 1 = the smallest Hellinger distance to the table.
  std::vector<std::size_t> order(fits.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return fits[a].hellinger < fits[b].hellinger;
  });
  for (std::size_t k = 0; k < order.size(); ++k) out[order[k]]["rank"] = k + 1;
  return out;
}

nlohmann::json stage_ndf_slices(const Context& c, const NdfSet& ndfs,
                                const std::vector<FitResult>& fits) {
  c.log("NDF cuts along x and y");
  nlohmann::json out = nlohmann::json::array();
  const TabulatedNdf& f = *ndfs.filtered;
  std::vector<std::shared_ptr<MicrofacetDistribution>> models;
  for (const auto& r : fits) models.push_back(fitted_distribution(r));
  for (int axis = 0; axis < 2; ++axis) {
    const double phi = axis == 0 ? 0.0 : M_PI / 2;
    const double rms = f.rms_slope(phi);
    const double theta_max = std::clamp(std::atan(6 * rms) * kDeg, 2.0, 89.0);
    const NdfSlice base = f.slice(phi, f.resolution());
    std::vector<std::size_t> keep;
    for (std::size_t i = 0; i < base.theta.size(); ++i)
      if (std::abs(base.theta[i] * kDeg) <= theta_max) keep.push_back(i);
    std::vector<double> theta_deg;
    for (auto i : keep) theta_deg.push_back(base.theta[i] * kDeg);
    nlohmann::json series = nlohmann::json::object();
    Plot p;
    p.title = std::string("NDF cut along ") + (axis == 0 ? "x" : "y") + " (log scale)";
    p.x.label =
        std::string("signed polar angle of m towards +") + (axis == 0 ? "x" : "y") + " (deg)";
    p.y.label = "D(m) (1/sr)";
    p.y.scale = AxisScale::Log;
    double peak = 0;
    auto add_table = [&](const char* key, const TabulatedNdf* t, PlotStyle style) {
      if (!t) return;
      const NdfSlice s = t->slice(phi, f.resolution());
      std::vector<double> v;
      for (auto i : keep) v.push_back(s.value[i]);
      for (double x : v) peak = std::max(peak, x);
      series[key] = finite_array(v);
      p.add(PlotSeries(theta_deg, v, std::string(key) + " (table)", style));
    };
    add_table("naive", ndfs.naive.get(), PlotStyle::Dotted);
    add_table("filtered", ndfs.filtered.get(), PlotStyle::Line);
    add_table("kirchhoff", ndfs.kirchhoff.get(), PlotStyle::Line);
    for (std::size_t k = 0; k < fits.size(); ++k) {
      std::vector<double> v;
      for (auto i : keep) {
        const double t = base.t[i];
        const Vec3 m(t * std::cos(phi), t * std::sin(phi), std::sqrt(std::max(0.0, 1 - t * t)));
        v.push_back(models[k]->D(m));
      }
      const std::string key = fits[k].model + "_fit";
      series[key] = finite_array(v);
      p.add(PlotSeries(theta_deg, v, fits[k].model + " fit", PlotStyle::Dashed));
    }
    p.x.min = -theta_max;
    p.x.max = theta_max;
    if (peak > 0) {
      p.y.min = peak * 1e-4;
      p.y.max = peak * 3;
    }
    const std::string svg = std::string("img/ndf_cut_") + (axis == 0 ? "x" : "y") + ".svg";
    p.write_svg(c.path(svg), 560, 380);
    out.push_back({{"axis", axis == 0 ? "x" : "y"},
                   {"azimuth_rad", phi},
                   {"theta_deg", finite_array(theta_deg)},
                   {"values_per_sr", series},
                   {"plot", svg}});
  }
  return out;
}

namespace {
constexpr int kReportMsWalks = 1;  // walks per eval of the multiple-scattering BRDF (unbiased)
std::vector<TabulatedNdf> dk_tables(const NdfSet& ndfs) {
  return ndfs.kirchhoff_stack.empty() ? std::vector<TabulatedNdf>{*ndfs.kirchhoff}
                                      : ndfs.kirchhoff_stack;
}
std::shared_ptr<MicrofacetDistribution> ellipsoid_of(const std::vector<FitResult>& fits) {
  for (const auto& r : fits)
    if (r.model == "ellipsoid") return fitted_distribution(r);
  return nullptr;
}
}  // namespace

std::shared_ptr<const Brdf> measured_brdf(const NdfSet& ndfs,
                                          const std::shared_ptr<const Fresnel>& fresnel,
                                          const OpticalConstants& material,
                                          const std::vector<FitResult>& fits) {
  if (ndfs.theory == "rayleigh-rice" && ndfs.psd)
    return std::make_shared<RayleighRiceBrdf>(ndfs.psd, material);
  if (ndfs.theory == "kirchhoff" && ndfs.kirchhoff)
    return std::make_shared<KirchhoffBrdf>(dk_tables(ndfs), fresnel, ellipsoid_of(fits));
  return std::make_shared<MicrofacetBrdf>(
      std::make_shared<TabulatedDistribution>(ndfs.for_render()), fresnel);
}

std::string measured_label(const NdfSet& ndfs) {
  if (ndfs.theory == "rayleigh-rice" && ndfs.psd) return "measured (Rayleigh-Rice, scan PSD)";
  if (ndfs.theory == "kirchhoff" && ndfs.kirchhoff)
    return ndfs.kirchhoff_stack.size() > 1 ? "measured (D_K over lambda_q)" : "measured (D_K)";
  return "measured (" + ndfs.render + " NDF)";
}

// How many fitted models the BRDF slices and the render comparison show (the best ranked).
constexpr std::size_t kStripModels = 3;

std::vector<NamedBrdf> model_brdfs(const NdfSet& ndfs, const std::vector<FitResult>& fits,
                                   const std::shared_ptr<const Fresnel>& fresnel) {
  std::vector<NamedBrdf> models;
  // The kStripModels fits closest to the table (Hellinger distance), in the fits' order.
  std::vector<double> h;
  for (const auto& r : fits) h.push_back(r.hellinger);
  std::sort(h.begin(), h.end());
  const double cut = h.empty() ? 0 : h[std::min(h.size(), kStripModels) - 1];
  std::size_t taken = 0;
  for (const auto& r : fits) {
    if (r.hellinger > cut || taken == kStripModels) continue;
    ++taken;
    models.push_back({r.model, r.model + " fit",
                      std::make_shared<MicrofacetBrdf>(fitted_distribution(r), fresnel)});
  }
  // Beside the run's theory, the others it computed: D_K (unless it is the measured BRDF) and,
  // for a Rayleigh-Rice run, the geometric BRDF of the filtered NDF.
  if (ndfs.kirchhoff && !(ndfs.theory == "kirchhoff"))
    models.push_back(
        {"kirchhoff", "Kirchhoff D_K (Dong eq. 8)",
         std::make_shared<KirchhoffBrdf>(dk_tables(ndfs), fresnel, ellipsoid_of(fits))});
  // The geometric BRDF of the NDF beside a wave-optics run, and with multiple scattering (one
  // walk per eval, unbiased: the renders' noise dominates) beside its single form.
  const bool geometric_run = ndfs.theory == "geometric";
  if (ndfs.filtered && !geometric_run &&
      (ndfs.theory == "rayleigh-rice" || ndfs.multiple_scattering))
    models.push_back({"geometric", "geometric (" + ms_table_name(ndfs) + " NDF), single scattering",
                      std::make_shared<MicrofacetBrdf>(
                          std::make_shared<TabulatedDistribution>(ms_table_of(ndfs)), fresnel)});
  if (ndfs.filtered && ndfs.multiple_scattering) {
    MultipleScatteringOptions mo;
    mo.eval_walks = kReportMsWalks;
    models.push_back(
        {"multiple_scattering", "geometric, single + multiple scattering",
         std::make_shared<MultipleScatteringBrdf>(
             std::make_shared<TabulatedDistribution>(ms_table_of(ndfs)), fresnel, mo)});
  }
  return models;
}

namespace {
double d_or_0(const nlohmann::json& v) { return v.is_number() ? v.get<double>() : 0.0; }
}  // namespace

nlohmann::json stage_brdf(const Context& c, const NdfSet& ndfs, const std::vector<FitResult>& fits,
                          const std::shared_ptr<const Fresnel>& fresnel,
                          const std::shared_ptr<const Brdf>& measured) {
  const auto& o = c.opt;
  std::vector<NamedBrdf> models;
  c.log("BRDF: " + measured_label(ndfs));
  models.push_back({"measured", measured_label(ndfs), measured});
  for (auto& m : model_brdfs(ndfs, fits, fresnel)) models.push_back(std::move(m));
  nlohmann::json jm = nlohmann::json::array();
  for (const auto& m : models)
    jm.push_back({{"key", m.key}, {"label", m.label}, {"description", m.brdf->describe()}});

  nlohmann::json slices = nlohmann::json::array(), albedo = nlohmann::json::array();
  for (double ti : o.slice_theta_i_rad) {
    const Vec3 wi(-std::sin(ti), 0, std::cos(ti));
    nlohmann::json a = {{"theta_i_rad", ti}, {"theta_i_deg", ti * kDeg}};
    for (const auto& m : models)
      a["albedo"][m.key] = directional_albedo_sampled(*m.brdf, wi, o.wavelength_m, 128);
    albedo.push_back(std::move(a));
    for (SlicePlane plane : {SlicePlane::In, SlicePlane::Out}) {
      const char* pname = plane == SlicePlane::In ? "in" : "out";
      c.log(std::string("BRDF: ") + pname + "-plane slice, theta_i " + std::to_string(ti * kDeg) +
            " deg");
      char title[120];
      std::snprintf(title, sizeof title, "BRDF %s-plane, θi = %.4g°, λ = %s", pname, ti * kDeg,
                    format_length(o.wavelength_m).c_str());
      const std::string x_label = plane == SlicePlane::In
                                      ? "θo in the plane of incidence (deg; mirror at +θi)"
                                      : "angle from the mirror direction across the plane (deg)";
      // The lobes of brushed metals are a fraction of a degree wide along the brushing: find
      // where any model exceeds 1e-5 of the highest peak on a coarse cut, then sample that range
      // densely (slice_samples points).
      double top = 0, lo = 90, hi = -90;
      std::vector<BrdfSlice> coarse;
      for (const auto& m : models)
        coarse.push_back(tabulate_slice(*m.brdf, ti, o.wavelength_m, plane, 1441));
      for (const auto& cs : coarse)
        for (double v : cs.value) top = std::max(top, v);
      for (const auto& cs : coarse)
        for (std::size_t i = 0; i < cs.value.size(); ++i)
          if (cs.value[i] > top * 1e-5) {
            lo = std::min(lo, cs.angle_deg[i]);
            hi = std::max(hi, cs.angle_deg[i]);
          }
      if (!(hi > lo)) lo = -90, hi = 90;
      lo = std::max(-89.9, lo - 1.0);
      hi = std::min(89.9, hi + 1.0);
      const std::vector<double> angles = even_angles(lo, hi, o.slice_samples);
      nlohmann::json values = nlohmann::json::object(), peaks = nlohmann::json::object();
      top = 0;
      std::vector<std::vector<double>> curves;
      for (std::size_t k = 0; k < models.size(); ++k) {
        const std::vector<double>& v =
            curves.emplace_back(slice_values(*models[k].brdf, ti, o.wavelength_m, plane, angles));
        std::size_t imax = 0;
        for (std::size_t i = 0; i < v.size(); ++i)
          if (v[i] > v[imax]) imax = i;
        top = std::max(top, v[imax]);
        values[models[k].key] = finite_array(v);
        peaks[models[k].key] = {{"value_per_sr", v[imax]}, {"angle_deg", angles[imax]}};
      }
      Plot p = slice_frame(title, x_label, lo, hi, top, 1e-5);
      for (std::size_t k = 0; k < models.size(); ++k)
        p.add(PlotSeries(angles, curves[k], models[k].label,
                         k == 0 ? PlotStyle::Line : PlotStyle::Dashed));
      char svg[64];
      std::snprintf(svg, sizeof svg, "img/brdf_%s_%02d.svg", pname,
                    static_cast<int>(std::lround(ti * kDeg)));
      p.write_svg(c.path(svg), 560, 380);
      nlohmann::json slice = {{"theta_i_rad", ti},     {"theta_i_deg", ti * kDeg},
                              {"plane", pname},        {"angle_deg", finite_array(angles)},
                              {"range_deg", {lo, hi}}, {"values_per_sr", values},
                              {"peak", peaks},         {"plot", svg}};
      // A narrow measured lobe (above a tenth of its peak over less than 1/15 of the axis): a
      // zoomed companion plot, +-3 of those widths about the peak, sampled afresh.
      {
        const auto& mv = values[models[0].key];
        const double mtop = d_or_0(peaks[models[0].key]["value_per_sr"]);
        double a0 = hi, a1 = lo;
        for (std::size_t i = 0; i < angles.size(); ++i)
          if (mv[i].is_number() && mv[i].get<double>() > 0.1 * mtop)
            a0 = std::min(a0, angles[i]), a1 = std::max(a1, angles[i]);
        const double width = std::max(a1 - a0, 2 * (hi - lo) / static_cast<double>(angles.size()));
        if (mtop > 0 && a1 >= a0 && width < (hi - lo) / 15) {
          const double mid = d_or_0(peaks[models[0].key]["angle_deg"]);
          const double zlo = std::max(lo, mid - std::max(3 * width, 0.25));
          const double zhi = std::min(hi, mid + std::max(3 * width, 0.25));
          const std::vector<double> za = even_angles(zlo, zhi, o.slice_samples);
          Plot z = slice_frame("zoom on the measured lobe", "angle (deg)", zlo, zhi, top, 1e-3);
          z.legend = LegendPlace::None;  // the same curves as the main plot's legend
          for (std::size_t k = 0; k < models.size(); ++k)
            z.add(PlotSeries(za, slice_values(*models[k].brdf, ti, o.wavelength_m, plane, za), "",
                             k == 0 ? PlotStyle::Line : PlotStyle::Dashed));
          char zsvg[64];
          std::snprintf(zsvg, sizeof zsvg, "img/brdf_%s_%02d_zoom.svg", pname,
                        static_cast<int>(std::lround(ti * kDeg)));
          z.write_svg(c.path(zsvg), 300, 380);
          slice["zoom"] = {{"range_deg", {zlo, zhi}}, {"plot", zsvg}};
        }
      }
      slices.push_back(std::move(slice));
    }
  }
  return {{"wavelength_m", o.wavelength_m},
          {"fresnel", fresnel->describe()},
          {"shadowing", "Smith height-correlated G2 of each model's distribution"},
          {"models", jm},
          {"albedo", albedo},
          {"slices", slices}};
}

}  // namespace microbrdf::report
