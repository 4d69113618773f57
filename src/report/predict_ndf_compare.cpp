// predict: --filter-sigma auto and the NDF comparison (predict_ndf_compare.hpp).
#include "report/predict_ndf_compare.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "microbrdf/atomic_file.hpp"
#include "microbrdf/ndf_preview.hpp"
#include "microbrdf/plot.hpp"
#include "microbrdf/units.hpp"
#include "report/html.hpp"

namespace microbrdf::report {
namespace {

constexpr double kAliasedWarn = 0.5;  // warn when D_K lost more than this to the Nyquist mask

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

}  // namespace

std::optional<FilterSigmaAuto> filter_sigma_sweep(
    const PredictOptions& o, const std::vector<std::string>& paths,
    const std::function<void(const std::string&)>& log) {
  if (!o.filter_sigma_auto) return std::nullopt;
  FilterSigmaAutoOptions fo;
  fo.resolution = o.filter_sigma_sweep_resolution;
  // The sweep compares shapes with a midpoint-rule D_K whatever the report's D_K uses
  // (docs/guide.md).
  fo.kirchhoff = o.kirchhoff_options;
  fo.kirchhoff.wavelength_q = o.wavelength_m;
  fo.kirchhoff.integration = KirchhoffIntegration::Midpoint;
  fo.kirchhoff.progress = nullptr;
  fo.log = log;
  return choose_filter_sigma(paths, o.read, o.leveling, fo);
}

nlohmann::json stage_ndf_comparison(const Context& c, const NdfSet& ndfs,
                                    const FilterSigmaAuto* sweep) {
  const auto& o = c.opt;
  // The tables compared: predict's own when D_K was computed at full size, else the sweep's.
  const TabulatedNdf *naive = ndfs.naive.get(), *filtered = ndfs.filtered.get(),
                     *kirchhoff = ndfs.kirchhoff.get();
  std::string source = "the report's tables";
  if (!kirchhoff && sweep) {
    naive = &sweep->naive;
    filtered = &sweep->filtered;
    kirchhoff = &sweep->kirchhoff;
    source = "the filter sigma sweep's small tables (D_K is slow at full size)";
  }
  nlohmann::json tables = nlohmann::json::object();
  auto describe = [&](const char* key, const TabulatedNdf* t) {
    if (!t) return;
    tables[key] = {{"slope_rms_x", t->rms_slope(0)},
                   {"slope_rms_y", t->rms_slope(M_PI / 2)},
                   {"filter_sigma_m", t->meta.filter_sigma_m},
                   {"wavelength_m", t->meta.wavelength_m}};
  };
  describe("naive", naive);
  describe("filtered", filtered);
  describe("kirchhoff", kirchhoff);
  // Previews side by side on one colour scale and one zoom window.
  double top = 0, slope = 0;
  for (const TabulatedNdf* t : {naive, filtered, kirchhoff})
    if (t)
      for (double v : t->values()) top = std::max(top, v);
  for (const TabulatedNdf* t : {naive, filtered, kirchhoff})
    if (t) slope = std::max({slope, t->rms_slope(0), t->rms_slope(M_PI / 2)});
  NdfPreviewOptions po;
  po.size = 260;
  po.zoom = true;
  po.max_value = top;
  po.zoom_half_width = std::clamp(4 * slope, 8 * naive->spacing(), 1.0);
  const std::pair<const char*, const TabulatedNdf*> shown[] = {
      {"naive", naive}, {"filtered", filtered}, {"kirchhoff", kirchhoff}};
  for (const auto& [key, t] : shown) {
    if (!t) continue;
    const std::string rel = std::string("img/ndf_compare_") + key + ".png";
    po.title = key == std::string("kirchhoff") ? "D_K" : key;
    write_ndf_preview(*t, c.path(rel), po);
    tables[key]["preview"] = rel;
  }
  const double h_nf = hellinger_distance(*naive, *filtered);
  const double h_nk = kirchhoff ? hellinger_distance(*naive, *kirchhoff) : NAN;
  const double h_fk = kirchhoff ? hellinger_distance(*filtered, *kirchhoff) : NAN;
  const std::string nearest = !kirchhoff ? "" : (h_nk < h_fk ? "naive" : "filtered");

  // Why the renders use what they use.
  const std::string sig = format_length(o.filter_sigma_m);
  std::string why;
  if (ndfs.render == "naive") {
    why = "the naive NDF, as asked with --render-ndf naive";
  } else if (ndfs.render == "kirchhoff") {
    why = "D_K over lambda_q (the Kirchhoff BRDF, Dong eq. 8), " +
          std::string(o.theory == "auto" && o.render_ndf != "kirchhoff"
                          ? "the theory the scans' regime picked (summary.json regime.theory)"
                          : "as asked (--theory kirchhoff or --render-ndf kirchhoff)");
  } else if (sweep) {
    why = "the filtered NDF (the default) at the filter sigma chosen by --filter-sigma auto, " +
          sig + ": of " + std::to_string(sweep->curve.size()) + " sigmas from " +
          format_length(sweep->sigma_min_m) + " to " + format_length(sweep->sigma_max_m) +
          ", the one whose filtered NDF is nearest D_K at lambda_q " +
          format_length(o.wavelength_m) + " (Hellinger distance " + fmt("%.4g", sweep->hellinger) +
          " on " + std::to_string(sweep->resolution) + "^2 tables)";
    if (sweep->at_lower_end)
      why +=
          "; the minimum lies at the smallest sigma swept (the sample spacing): D_K is "
          "closest to the least filtered surface, i.e. to the naive NDF";
    else if (sweep->at_upper_end)
      why += "; the minimum lies at the largest sigma swept";
  } else {
    why = "the filtered NDF (the default), filter sigma " + sig +
          " as given (--filter-sigma; 1 um by default, about two wavelengths of green light, "
          "Dong 2015 sec. 5.1); the sigma is not checked against D_K (--filter-sigma auto "
          "chooses it)";
  }
  // Nearer by less than this is within the speckle of D_K and the sampling of the tables.
  constexpr double kNearerBy = 0.01;
  const double h_render = ndfs.render == "naive" ? h_nk : h_fk;
  const double h_nearest = nearest == "naive" ? h_nk : h_fk;
  if (kirchhoff && ndfs.render != "kirchhoff" && nearest != ndfs.render &&
      h_render - h_nearest > kNearerBy) {
    char b[320];
    std::snprintf(b, sizeof b,
                  "D_K at lambda_q %s is nearer the %s NDF (Hellinger distance %.4g) than the %s "
                  "NDF the renders use (%.4g)",
                  format_length(o.wavelength_m).c_str(), nearest.c_str(), h_nearest,
                  ndfs.render.c_str(), h_render);
    why += std::string("; note: ") + b;
    c.warn("render_ndf_not_nearest_dk", b,
           "render with --render-ndf " + nearest +
               (nearest == "naive" ? "" : " (or --filter-sigma auto)") +
               " if the wave-optics D_K is the reference you trust; the report shows both");
  }
  if (sweep && (sweep->at_lower_end || sweep->at_upper_end) && ndfs.render == "filtered") {
    c.warn("filter_sigma_auto_at_end",
           "--filter-sigma auto found its minimum at the " +
               std::string(sweep->at_lower_end ? "smallest" : "largest") + " sigma swept (" +
               format_length(sweep->sigma_m) + " of " + format_length(sweep->sigma_min_m) + " .. " +
               format_length(sweep->sigma_max_m) + ")",
           sweep->at_lower_end
               ? "D_K is closest to the unfiltered slopes: the naive NDF (--render-ndf naive) "
                 "describes the surface at lambda_q as well; a finer scan would let the sweep "
                 "go lower"
               : "a larger scan would let the sweep go higher; or give --filter-sigma");
  }

  if (sweep && sweep->kirchhoff_aliased_fraction > kAliasedWarn) {
    char b[320];
    std::snprintf(b, sizeof b,
                  "%.1f%% of the mass of the D_K that --filter-sigma auto compares with lies "
                  "beyond the scan's Nyquist band (a sample spacing above lambda_q / 4 = %s) and "
                  "was removed: the chosen sigma rests on a small band of directions about the "
                  "pole",
                  100 * sweep->kirchhoff_aliased_fraction,
                  format_length(sweep->wavelength_q_m / 4).c_str());
    c.warn("filter_sigma_auto_aliased", b,
           "wave optics needs a scan sampled finer than lambda_q / 4; with this scan give "
           "--filter-sigma (or render the naive NDF) instead of auto");
  }
  nlohmann::json out = {
      {"source", source},
      {"resolution", naive->resolution()},
      {"tables", tables},
      {"hellinger",
       {{"naive_filtered", h_nf}, {"naive_kirchhoff", h_nk}, {"filtered_kirchhoff", h_fk}}},
      {"nearest_to_kirchhoff", nearest.empty() ? nlohmann::json(nullptr) : nlohmann::json(nearest)},
      {"render_ndf", ndfs.render},
      {"render_reason", why},
      {"filter_sigma_m", o.filter_sigma_m},
      {"filter_sigma_auto", nullptr}};
  if (!sweep) return out;
  out["filter_sigma_auto"] = sweep->to_json();
  write_filter_sigma_curve_csv(*sweep, c.path("filter_sigma_curve.csv"));
  out["filter_sigma_auto"]["curve_csv"] = "filter_sigma_curve.csv";
  Plot p;
  p.title = "Filtered NDF against D_K (lambda_q " + format_length(o.wavelength_m) + ")";
  p.x.label = "filter sigma (um)";
  p.x.scale = AxisScale::Log;
  p.y.label = "Hellinger distance to D_K";
  std::vector<double> xs, ys;
  for (const auto& q : sweep->curve) {
    xs.push_back(q.sigma_m * 1e6);
    ys.push_back(q.hellinger);
  }
  p.add({xs, ys, "filtered NDF", PlotStyle::LineMarkers});
  p.add({{xs.front(), xs.back()},
         {sweep->hellinger_naive_kirchhoff, sweep->hellinger_naive_kirchhoff},
         "naive NDF",
         PlotStyle::Dashed});
  auto& chosen = p.add({{sweep->sigma_m * 1e6}, {sweep->hellinger}, "chosen", PlotStyle::Markers});
  chosen.marker = MarkerShape::Diamond;
  chosen.marker_size = 6;
  p.write_svg(c.path("img/filter_sigma_curve.svg"), 640, 400);
  out["filter_sigma_auto"]["curve_plot"] = "img/filter_sigma_curve.svg";
  return out;
}

std::string ndf_comparison_html(const nlohmann::json& summary, const std::string& dir) {
  if (!summary.contains("ndf_comparison") || !summary["ndf_comparison"].is_object()) return "";
  const auto& j = summary["ndf_comparison"];
  auto num_of = [](const nlohmann::json& v) { return num_or(v, "—"); };
  std::ostringstream p;
  p << "<h3 id=\"ndf-compare\">Which NDF: naive, filtered and D_K compared</h3>\n<table>\n"
       "<tr><th>NDF</th><th>rms slope x</th><th>rms slope y</th><th>filter sigma</th>"
       "<th>Hellinger distance to D_K</th></tr>\n";
  const auto& t = j["tables"];
  const auto& h = j["hellinger"];
  const std::pair<const char*, const char*> rows[] = {
      {"naive", "naive_kirchhoff"}, {"filtered", "filtered_kirchhoff"}, {"kirchhoff", ""}};
  for (const auto& [k, hk] : rows) {
    if (!t.contains(k)) continue;
    const auto& r = t[k];
    const double fs = r.value("filter_sigma_m", 0.0);
    p << "<tr><td>" << (std::string(k) == "kirchhoff" ? "D_K" : k)
      << (j.value("render_ndf", "") == k ? " (renders)" : "") << "</td><td class=\"n\">"
      << num_of(r["slope_rms_x"]) << "</td><td class=\"n\">" << num_of(r["slope_rms_y"])
      << "</td><td class=\"n\">" << (fs > 0 ? length(fs) : "—") << "</td><td class=\"n\">"
      << (*hk ? num_of(h[hk]) : "0") << "</td></tr>\n";
  }
  p << "</table>\n<div class=\"grid\">";
  for (const auto& [k, hk] : rows) {
    (void)hk;
    if (!t.contains(k) || !t[k].contains("preview")) continue;
    const std::string file =
        (std::filesystem::path(dir) / t[k]["preview"].get<std::string>()).string();
    const std::string name = std::string(k) == "kirchhoff" ? "D_K" : k;
    p << "<figure><img src=\"" << data_uri(file, "image/png") << "\" alt=\"NDF " << name
      << "\" width=\"390\"><figcaption>" << name
      << (j.value("render_ndf", "") == k ? " (the renders use it)" : "")
      << "</figcaption></figure>";
  }
  p << "</div>\n<p class=\"cap\">The three tables on one logarithmic colour scale (decades of "
       "1/sr below the largest value of the three) with the same zoom window about the pole.</p>\n"
       "<p>Hellinger distance naive–filtered "
    << num_of(h["naive_filtered"]) << ", naive–D_K "
    << num_or(h["naive_kirchhoff"], "— (D_K not computed)") << ", filtered–D_K "
    << num_or(h["filtered_kirchhoff"], "— (D_K not computed)") << ", on "
    << escape(j.value("source", "")) << ", " << std::to_string(j.value("resolution", 0))
    << "&sup2; nodes. H&sup2; = 1 − Σ √(p q) over the table, p and q the nodes' probabilities "
       "D(m)(m·n)dω: 0 for equal NDFs, 1 for NDFs with no node in common.";
  if (!t.contains("kirchhoff"))
    p << " Give <code>--kirchhoff</code> or <code>--filter-sigma auto</code> to compare with "
         "D_K.";
  p << "</p>\n<p><b>The renders use</b> " << escape(j.value("render_reason", ""))
    << ". Pick another with <code>--render-ndf naive|filtered|kirchhoff</code>; the fits are of "
       "the filtered NDF.</p>\n";
  const auto& a = j["filter_sigma_auto"];
  if (a.is_object() && a.contains("curve_plot"))
    p << "<figure>"
      << inline_svg((std::filesystem::path(dir) / a["curve_plot"].get<std::string>()).string(),
                    "ndfcmp-")
      << "<figcaption>--filter-sigma auto: Hellinger distance of the filtered NDF to D_K over the "
         "sweep (log-spaced from the sample spacing, refined around the minimum; "
      << std::to_string(a["sweep"].value("resolution", 0))
      << "&sup2; tables); dashed: the naive NDF. Curve: <code>" << escape(a.value("curve_csv", ""))
      << "</code>.</figcaption></figure>\n";
  return p.str();
}

}  // namespace microbrdf::report
