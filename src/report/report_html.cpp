// report.html from summary.json: every number shown comes from the summary (so summary.json holds
// every number of the report), printed with its unit; images and plots are embedded.
#include <cmath>
#include <filesystem>
#include <sstream>
#include <utility>

#include "microbrdf/error.hpp"
#include "microbrdf/predict.hpp"
#include "report/gltf_view.hpp"
#include "report/html.hpp"
#include "report/material_view.hpp"
#include "report/ndf_hover.hpp"
#include "report/predict_measured.hpp"
#include "report/predict_multiple_scattering.hpp"
#include "report/predict_ndf_compare.hpp"
#include "report/predict_regime.hpp"

namespace microbrdf {
namespace {

using nlohmann::json;
using report::escape;

constexpr double kDeg = 180.0 / M_PI;

// A quantity that does not exist for this input (null in the summary, e.g. the skewness of a
// flat scan) reads "— (not defined for this input)" (report::num), never nan.
double d(const json& v) { return v.is_number() ? v.get<double>() : std::nan(""); }
std::string n4(const json& v) { return report::num(d(v)); }
std::string len(const json& v) { return report::length(d(v)); }
std::string deg(const json& v) {
  return std::isfinite(d(v)) ? report::num(d(v) * kDeg) + " deg" : report::num(d(v));
}
std::string str(const json& v) { return v.is_string() ? v.get<std::string>() : v.dump(); }

// One SI length unit for a row of values (the prefix of the largest magnitude), so the unit
// column says what the numbers are in.
struct LengthUnit {
  double scale;
  const char* name;
};
std::vector<double> row_values(json& inputs, const char* key) {
  std::vector<double> v;
  for (auto& in : inputs)
    v.push_back(in["stats"][key].is_number() ? in["stats"][key].get<double>() : std::nan(""));
  return v;
}
LengthUnit length_unit(const std::vector<double>& values) {
  double a = 0;
  for (double v : values)
    if (std::isfinite(v)) a = std::max(a, std::fabs(v));
  static constexpr LengthUnit kUnits[] = {
      {1, "m"}, {1e-3, "mm"}, {1e-6, "um"}, {1e-9, "nm"}, {1e-12, "pm"}};
  for (const auto& u : kUnits)
    if (a >= u.scale * 0.9995) return u;
  return a > 0 ? kUnits[4] : kUnits[2];
}
// `text` with every " (source)" replaced: the material's citation is printed once (section 5).
std::string uncite(std::string text, const json& source, const std::string& replacement) {
  if (!source.is_string() || source.get<std::string>().empty()) return text;
  const std::string cite = " (" + source.get<std::string>() + ")";
  for (auto at = text.find(cite); at != std::string::npos; at = text.find(cite, at))
    text.replace(at, cite.size(), replacement), at += replacement.size();
  return text;
}

// A file's date; a zero time stamp (1970-01-01, the Unix epoch) is no date.
std::string date_text(const json& v) {
  const std::string d = v.is_string() ? v.get<std::string>() : "";
  if (d.empty()) return "unknown (not stated in the file)";
  if (d.rfind("1970-01-01", 0) == 0) return "unknown (the file holds a zero time stamp)";
  return escape(d);
}
std::string or_dash(const json& v, const std::string& missing) {
  const std::string s = v.is_string() ? v.get<std::string>() : "";
  return s.empty() ? missing : s;
}

const char* kStyle = R"(
body{font-family:"DejaVu Sans",Helvetica,Arial,sans-serif;margin:0 auto;max-width:1240px;
  padding:16px 24px;color:#1d1d1f;background:#fff;font-size:14px;line-height:1.45}
h1{font-size:26px;margin:8px 0 4px} h2{font-size:20px;margin:28px 0 8px;border-bottom:2px solid #ddd;
  padding-bottom:4px} h3{font-size:16px;margin:16px 0 6px}
table{border-collapse:collapse;margin:6px 0 4px} th,td{border:1px solid #ccc;padding:3px 8px;
  text-align:left;vertical-align:top} th{background:#f2f2f5} td.n{text-align:right;
  font-variant-numeric:tabular-nums;white-space:nowrap}
.cap{color:#555;font-size:12.5px;margin:2px 0 12px;max-width:1100px}
.grid{display:flex;flex-wrap:wrap;gap:14px;align-items:flex-start}
figure{margin:0} figcaption{font-size:12.5px;color:#444;max-width:600px}
.note{background:#fff7e0;border:1px solid #e8c96a;padding:6px 10px;display:inline-block}
.swatch{display:inline-block;width:28px;height:16px;border:1px solid #888;vertical-align:middle}
figure svg{width:600px;max-width:100%;height:auto;display:block} figure img{max-width:100%;height:auto}
table{max-width:100%;display:block;overflow-x:auto} td,th{overflow-wrap:break-word}
code{overflow-wrap:anywhere}
.mbv{display:flex;flex-wrap:wrap;gap:18px;align-items:flex-start}
.mbv canvas{width:384px;height:384px;border:1px solid #ccc;background:#222}
.mbv-controls div{margin:4px 0} .mbv-controls label{margin-right:10px}
#mbv-lobe{width:320px;height:320px;border:1px solid #ccc;cursor:crosshair}
.mbv-bar{display:flex;flex-direction:column;align-items:flex-start;font-size:12px;gap:2px}
.mbv-ramp{width:18px;height:280px;border:1px solid #888}
.cbar{height:12px;border:1px solid #888;margin-top:4px} figure.tex{display:table} figure.tex figcaption{display:table-caption;caption-side:bottom} .cbar-l{display:flex;
  justify-content:space-between;font-size:12px;color:#444}
.warnbox{background:#fff1ee;border:2px solid #d9534f;padding:6px 12px;margin:10px 0;max-width:1100px}
.warnbox.ok{background:#f0f8f0;border:1px solid #8bc58b} .warnbox li{margin:4px 0}
.warnbox .todo{color:#333}
.zpair{display:flex;gap:6px;align-items:flex-start} figure.zoomed svg{width:560px}
figure.zoomed .zoomp svg{width:300px}
nav.toc{background:#f6f6f8;border:1px solid #ddd;padding:6px 12px;display:inline-block}
nav.toc ol{margin:4px 0;padding-left:22px} details summary{cursor:pointer;color:#444}
)";

class Page {
 public:
  explicit Page(std::string dir) : dir_(std::move(dir)) {}
  Page& operator<<(const std::string& s) {
    out_ << s;
    return *this;
  }
  std::string image(const std::string& rel, const std::string& alt, int width = 0) {
    const std::string p = (std::filesystem::path(dir_) / rel).string();
    std::string w = width > 0 ? " width=\"" + std::to_string(width) + "\"" : "";
    return "<img src=\"" + report::data_uri(p, "image/png") + "\" alt=\"" + escape(alt) + "\"" + w +
           ">";
  }
  std::string svg(const std::string& rel) {
    std::string prefix = "s";  // built in steps: GCC 12 warns (-Wrestrict) on "s" + to_string()
    prefix += std::to_string(++svgs_);
    prefix += '-';
    return report::inline_svg((std::filesystem::path(dir_) / rel).string(), prefix);
  }
  std::string str() const { return out_.str(); }
  std::string path(const std::string& rel) const {
    return (std::filesystem::path(dir_) / rel).string();
  }

 private:
  std::string dir_;
  std::ostringstream out_;
  int svgs_ = 0;
};

std::string row(std::initializer_list<std::string> cells, bool header = false) {
  std::string r = "<tr>";
  bool first = true;
  for (const auto& c : cells) {
    const bool numeric = !header && !first && !c.empty() && (std::isdigit(c[0]) || c[0] == '-');
    r += header ? "<th>" : (numeric ? "<td class=\"n\">" : "<td>");
    r += c;
    r += header ? "</th>" : "</td>";
    first = false;
  }
  return r + "</tr>\n";
}

std::string corr(const json& v) {
  return v.is_number() && std::isfinite(d(v)) ? len(v)
                                              : "not reached (ACF stays above 1/e over the scan)";
}

// Every warning the run printed (summary.json "warnings"), each with what to do about it, at
// the top of the page: a reader sees them before any number they qualify.
void warnings_box(Page& p, json& s) {
  json& w = s["warnings"];
  if (!w.is_array() || w.empty()) {
    p << "<div class=\"warnbox ok\" id=\"warnings\"><b>Warnings: none.</b> No check of the run "
         "(filter sigma against the sample spacing, lobe width against the table, fits at a bound "
         "or poor, low-order form, invalid samples) raised one.</div>\n";
    return;
  }
  p << "<div class=\"warnbox\" id=\"warnings\"><b>Warnings (" << std::to_string(w.size())
    << ")</b>: read these before the numbers below (also in <code>summary.json</code> "
       "\"warnings\").<ol>";
  for (auto& e : w)
    p << "<li><code>" << escape(str(e["code"])) << "</code> " << escape(str(e["message"]))
      << ".<br><span class=\"todo\"><b>What to do:</b> " << escape(str(e["what_to_do"]))
      << ".</span></li>";
  p << "</ol></div>\n";
}

// "yes", or "no (at the lower alpha bound 0.000488 (alpha_x, alpha_y))" / "no (solver: ...)".
std::string converged_text(json& f) {
  if (f["converged"].is_boolean() && f["converged"].get<bool>()) return "yes";
  if (f["at_bound"].is_string()) return "no (at " + escape(str(f["at_bound"])) + ")";
  return "no (" + escape(str(f["termination"])) + ")";
}

void section_inputs(Page& p, json& s) {
  p << "<h2 id=\"s1\">1. Inputs</h2>\n<table>\n"
    << row({"#", "file", "format", "instrument", "date", "grid", "spacing dx &times; dy", "size",
            "valid", "levelling"},
           true);
  int i = 0;
  for (auto& in : s["inputs"]) {
    auto& st = in["stats"];
    p << row(
        {std::to_string(++i), "<code>" + escape(str(in["path"])) + "</code>",
         escape(or_dash(in["format"], "—")),
         escape(or_dash(in["instrument"], "not stated in the file")), date_text(in["date"]),
         std::to_string(st["nx"].get<long>()) + " &times; " + std::to_string(st["ny"].get<long>()),
         len(st["dx_m"]) + " &times; " + len(st["dy_m"]),
         len(st["width_m"]) + " &times; " + len(st["height_m"]),
         report::num(d(st["valid_fraction"]) * 100, 5) + " %",
         str(in["leveling_description"]).size() > 60
             ? "<details><summary>" + escape(str(in["leveling_description"]).substr(0, 40)) +
                   "&hellip;</summary>" + escape(str(in["leveling_description"])) + "</details>"
             : escape(str(in["leveling_description"]))});
  }
  p << "</table>\n<p class=\"cap\">Provenance: read by microbrdf's own readers (format, instrument "
       "and date as the file states them); levelled by least squares on the valid samples "
       "(<code>level_surface</code>); heights in metres inside, shown with SI prefixes. Invalid "
       "samples are excluded everywhere, never filled.</p>\n<div class=\"grid\">";
  i = 0;
  for (auto& in : s["inputs"]) {
    p << "<figure>" << p.image(str(in["preview"]), "height map " + str(in["name"]), 480)
      << "<figcaption>Height map " << std::to_string(++i) << ": " << escape(str(in["name"]))
      << " after levelling (false colour, 0.5&ndash;99.5th percentile, hill-shaded; grey = "
         "invalid).</figcaption></figure>";
  }
  p << "</div>\n";
}

void section_stats(Page& p, json& s) {
  p << "<h2 id=\"s2\">2. Surface statistics</h2>\n<table>\n<tr><th>quantity</th><th>unit</th>";
  int i = 0;
  for (auto& in : s["inputs"])
    p << "<th>" + std::to_string(++i) + ": " + escape(str(in["name"])) + "</th>";
  p << "<th>definition</th></tr>\n";
  struct Q {
    const char* key;
    const char* label;
    const char* unit;
    int kind;  // 0 length, 1 plain, 2 percent of valid, 3 correlation length
    const char* def;
  };
  const Q qs[] = {
      {"sq_m", "Sq (rms height, sigma)", "m", 0, "rms of the heights about their mean"},
      {"sa_m", "Sa (mean absolute height)", "m", 0, "mean |z - mean|"},
      {"min_m", "lowest valid height", "m", 0, "relative to the levelled plane"},
      {"max_m", "highest valid height", "m", 0, "relative to the levelled plane"},
      {"skewness", "Ssk (skewness)", "1", 1, "third moment / Sq^3 (0 for Gaussian)"},
      {"kurtosis", "Sku (kurtosis)", "1", 1, "fourth moment / Sq^4 (3 for Gaussian)"},
      {"slope_rms_x", "rms slope dz/dx", "1", 1,
       "central differences of the heights at the scan spacing (no smoothing)"},
      {"slope_rms_y", "rms slope dz/dy", "1", 1, "the same along y"},
      {"corr_length_x_m", "correlation length along x", "m", 3,
       "lag where the normalised ACF falls to 1/e (tau of exp(-r^2/tau^2))"},
      {"corr_length_y_m", "correlation length along y", "m", 3, "the same along y"},
      {"corr_length_m", "correlation length, radial", "m", 3, "the same, annular average"},
  };
  for (auto& q : qs) {
    // Lengths: one unit per row, the numbers printed in it.
    const bool length = q.kind == 0 || q.kind == 3;
    const LengthUnit u = length_unit(row_values(s["inputs"], q.key));
    p << "<tr><td>" << q.label << "</td><td>" << (length ? u.name : q.unit) << "</td>";
    for (auto& in : s["inputs"]) {
      json& v = in["stats"][q.key];
      std::string cell = !length                                ? n4(v)
                         : v.is_number() && std::isfinite(d(v)) ? report::num(d(v) / u.scale)
                         : q.kind == 3                          ? corr(v)
                                                                : n4(v);
      p << "<td class=\"n\">" << cell << "</td>";
    }
    p << "<td>" << q.def << "</td></tr>\n";
  }
  p << "</table>\n<p class=\"cap\">Provenance: <code>compute_stats</code> on each levelled scan "
       "(Sun 2002 sec. 3.1, Dong 2015 sec. 4); ACF by zero-padded FFTs, mask-aware.</p>\n";
}

void section_ndf(Page& p, json& s) {
  json& ndf = s["ndf"];
  p << "<h2 id=\"s3\">3. Normal distribution functions</h2>\n<div class=\"grid\">";
  const std::pair<const char*, const char*> kinds[] = {
      {"naive",
       "Naive NDF: two triangles per grid cell, projected-area weighted (Dong 2015 "
       "sec. 5.1)."},
      {"filtered",
       "Filtered NDF: normals of Gaussian-weighted local plane fits (Dong 2015 sec. "
       "5.1); the table the BRDF and the fits use."},
      {"kirchhoff", "Kirchhoff D_K (Dong 2015 eq. 6, App. A), wave optics at lambda_q."}};
  bool hover = false;
  for (auto& [k, cap] : kinds) {
    if (!ndf.contains(k)) continue;
    // The preview with an id, and D(m) under the pointer (ndf_hover.hpp).
    const std::string id = std::string("ndf-img-") + k;
    std::string img = p.image(str(ndf[k]["preview"]), std::string("NDF ") + k, 600);
    img.insert(4, " id=\"" + id + "\"");
    const std::string values = report::ndf_hover_html(p.path(str(ndf[k]["file"])), id);
    hover = hover || !values.empty();
    p << "<figure>" << img << values << "<figcaption>" << cap
      << " Log colour scale (decades of 1/sr), m_x right, m_y up; right panel zoomed on "
         "the peak.</figcaption></figure>";
  }
  p << "</div>\n";
  if (hover) p << report::ndf_hover_script();
  p << "<table>\n<tr><th>quantity</th><th>unit</th>";
  for (auto& [k, cap] : kinds)
    if (ndf.contains(k)) p << "<th>" << k << "</th>";
  p << "</tr>\n";
  auto line = [&](const char* label, const char* unit, auto fmt) {
    p << "<tr><td>" << label << "</td><td>" << unit << "</td>";
    for (auto& [k, cap] : kinds)
      if (ndf.contains(k)) p << "<td class=\"n\">" << fmt(ndf[k]) << "</td>";
    p << "</tr>\n";
  };
  line("table size", "nodes", [](json& j) {
    return std::to_string(j["resolution"].get<long>()) + " &times; " +
           std::to_string(j["resolution"].get<long>());
  });
  line("integral of D(m)(m.n) dω", "1", [](json& j) { return report::num(d(j["integral"]), 8); });
  line("rms slope along x (see below)", "1", [](json& j) { return n4(j["slope_rms_x"]); });
  line("rms slope along y", "1", [](json& j) { return n4(j["slope_rms_y"]); });
  line("Beckmann alpha_x = √2 rms slope", "1", [](json& j) { return n4(j["beckmann_alpha_x"]); });
  line("Beckmann alpha_y = √2 rms slope", "1", [](json& j) { return n4(j["beckmann_alpha_y"]); });
  line("anisotropy (rms slope max / min)", "1", [](json& j) { return n4(j["anisotropy"]); });
  line("smooth axis (scratches run along it), from +x", "deg",
       [](json& j) { return report::num(d(j["smooth_axis_angle_rad"]) * kDeg); });
  line("tilt of the mean normal", "deg",
       [](json& j) { return report::num(d(j["mean_normal_tilt_rad"]) * kDeg); });
  line("elements used", "count",
       [](json& j) { return std::to_string(j["samples_used"].get<long>()); });
  line("elements skipped", "count",
       [](json& j) { return std::to_string(j["samples_skipped"].get<long>()); });
  auto unit_of = [&](const char* key) {
    std::vector<double> v;
    for (auto& [k, cap] : kinds)
      if (ndf.contains(k)) v.push_back(d(ndf[k][key]));
    return length_unit(v);
  };
  const LengthUnit us = unit_of("filter_sigma_m"), uw = unit_of("wavelength_m");
  line("filter sigma", us.name, [&](json& j) {
    return d(j["filter_sigma_m"]) > 0 ? report::num(d(j["filter_sigma_m"]) / us.scale)
                                      : std::string("— (not filtered)");
  });
  line("wavelength lambda_q", uw.name, [&](json& j) {
    return d(j["wavelength_m"]) > 0 ? report::num(d(j["wavelength_m"]) / uw.scale)
                                    : std::string("— (geometric)");
  });
  p << "</table>\n<p class=\"cap\">Why the rms slopes differ: section 2 differentiates the "
       "heights at the scan spacing; the naive NDF takes the normals of the scan's triangles "
       "(the same scale, weighted by projected area); the filtered NDF takes normals of planes "
       "fitted over a Gaussian window of the filter sigma, which removes slopes on shorter "
       "scales, so its rms slope is smaller; D_K is the wave-optics distribution at lambda_q, "
       "which blurs what is finer than the wavelength. The BRDF and the fits use the filtered "
       "one.</p>\n<p class=\"cap\">Provenance: <code>NdfAccumulator</code> (naive, filtered) and "
       "<code>KirchhoffAccumulator</code> over all scans, one scan in memory at a time, weighted "
       "by projected area; tables on the orthographic disk, normalised to ∫D(m)(m.n)dω = 1; "
       "slopes from the table's slope covariance. Files: ";
  for (auto& [k, cap] : kinds)
    if (ndf.contains(k)) p << "<code>" << escape(str(ndf[k]["file"])) << "</code> ";
  if (ndf.contains("kirchhoff"))
    p << ". D_K: " << std::to_string(ndf["kirchhoff"]["patches"].get<long>()) << " patches of "
      << len(ndf["kirchhoff"]["patch_m"][0]) << " &times; " << len(ndf["kirchhoff"]["patch_m"][1])
      << ", integral before normalising " << n4(ndf["kirchhoff"]["raw_integral"])
      << ", fraction beyond the Nyquist band " << n4(ndf["kirchhoff"]["aliased_fraction"]);
  p << "</p>\n<h3>Cuts through the NDF, measured and fitted</h3>\n<div class=\"grid\">";
  for (auto& cut : s["ndf_cuts"]) p << "<figure>" << p.svg(str(cut["plot"])) << "</figure>";
  p << "</div>\n";
}

void exports_block(Page& p, json& s);

void section_fits(Page& p, json& s) {
  p << "<h2 id=\"s4\">4. Parametric fits of the filtered NDF</h2>\n<table>\n"
    << row({"rank", "model", "verdict", "alpha_x", "alpha_y", "theta_x", "theta_y", "theta_z",
            "other parameters", "rms error (1/sr)", "relative L2 error", "Hellinger distance",
            "iterations", "converged"},
           true);
  for (auto& f : s["fits"]) {
    auto& q = f["params"];
    const bool ell = str(f["model"]) == "ellipsoid";
    // The model's parameters beyond the common ones (e.g. a tail exponent).
    std::string other;
    for (auto& [k, v] : q.items())
      if (k != "alpha_x" && k != "alpha_y" && k != "theta_x" && k != "theta_y" && k != "theta_z" &&
          k != "phi" && v.is_number())
        other += (other.empty() ? "" : ", ") + escape(k) + " " + n4(v);
    p << row({f.contains("rank") ? str(f["rank"]) : "—", escape(str(f["model"])),
              "<b>" + escape(str(f["verdict"])) + "</b>", n4(q["alpha_x"]), n4(q["alpha_y"]),
              ell ? deg(q["theta_x"]) : "— (none in this model)",
              ell ? deg(q["theta_y"]) : "— (none in this model)", deg(q["theta_z"]),
              other.empty() ? "— (none)" : other, n4(f["rms_error"]), n4(f["relative_l2_error"]),
              n4(f["hellinger"]), std::to_string(f["iterations"].get<long>()), converged_text(f)});
  }
  p << "</table>\n<p class=\"cap\">Every registered model, ranked by Hellinger distance to the "
       "table (rank 1 the closest). Provenance: <code>fit_ndf</code> (Levenberg-Marquardt with "
       "the models' derivatives, coarse-to-fine; least squares on sqrt(D), a Hellinger distance; "
       "model averaged over each node's tent "
       "cell) of the filtered NDF. alpha dimensionless; angles in the ellipsoid convention "
       "(Dong 2015 eqs. 10-12): theta_x, theta_y tilt the peak, the anisotropy axes are turned "
       "by -theta_z (Beckmann/GGX phi = -theta_z). Errors over all disk nodes: rms = "
       "sqrt(mean (T-M)^2), relative L2 = |T-M|/|T|. Verdict: <b>good</b> = converged, relative "
       "L2 error under 0.2 and Hellinger distance under 0.1; <b>usable</b> = converged, relative "
       "L2 error under 0.45; <b>poor</b> = anything else: do not use its parameters "
       "(docs/report.md, \"Fit verdicts\").</p>\n";
  for (auto& f : s["fits"])
    if (f.contains("compare_image"))
      // Colour bars under the three panels (320 px each, 10 px gaps, 1010 px in all): the two
      // NDFs on a log scale, 4 decades below the table's maximum; the residual diverging.
      p << "<figure style=\"width:1010px;max-width:100%\">"
        << p.image(str(f["compare_image"]), "ellipsoid fit comparison")
        << "<div style=\"display:flex;gap:0.99%;padding-left:0.99%\">"
        << "<div style=\"width:31.68%\"><div class=\"cbar\" style=\"background:"
        << report::colour_gradient("to right")
        << "\"></div><div class=\"cbar-l\"><span>10<sup>-4</sup> max</span><span>D (log), "
           "measured</span><span>max (printed)</span></div></div>"
        << "<div style=\"width:31.68%\"><div class=\"cbar\" style=\"background:"
        << report::colour_gradient("to right")
        << "\"></div><div class=\"cbar-l\"><span>10<sup>-4</sup> max</span><span>D (log), "
           "fit</span><span>max</span></div></div>"
        << "<div style=\"width:31.68%\"><div class=\"cbar\" style=\"background:linear-"
           "gradient(to right,rgb(51,51,255),#fff,rgb(255,51,51))\"></div><div "
           "class=\"cbar-l\"><span>&minus;R</span><span>0</span><span>+R (R printed, a "
           "fraction of max)</span></div></div></div>"
        << "<figcaption>Ellipsoid fit: measured | fit | residual (M &minus; T) / max T, zoomed "
           "on the region of interest. Measured and fit share one log colour scale from the "
           "table's maximum (printed under the first panel, in 1/sr) down 4 decades; the "
           "residual runs from &minus;R (blue, fit below the measurement) to +R (red), R "
           "printed under it.</figcaption></figure>\n";
  exports_block(p, s);
}

// Links to the renderer-ready materials predict wrote (summary "exports").
void exports_block(Page& p, json& s) {
  if (!s.contains("exports") || !s["exports"].is_object()) return;
  json& e = s["exports"];
  p << "<h3 id=\"exports\">Renderer-ready materials</h3>\n<p>Each fit as a GGX rough conductor "
       "with this run's optical constants, with a sphere scene under a constant white emitter, "
       "and as glTF 2.0 (<code>KHR_materials_anisotropy</code> on a sphere and a plate, for "
       "real-time viewers; docs/gltf.md) (in <code>export/</code> beside this page; the links "
       "open the files):</p>\n<table>\n"
    << row({"fit", "GGX alpha_u", "GGX alpha_v", "Mitsuba 3", "pbrt-v4", "glTF 2.0",
            "approximations"},
           true);
  for (auto& m : e["materials"]) {
    auto links = [&](json& files) {
      std::string l;
      for (auto& f : files) {
        const std::string path = str(f);
        l += (l.empty() ? "" : " ");
        l += "<a href=\"" + escape(path) + "\"><code>" +
             escape(path.substr(path.find_last_of('/') + 1)) + "</code></a>";
      }
      return l;
    };
    std::string notes;
    for (auto& n : m["notes"]) notes += (notes.empty() ? "" : "; ") + escape(str(n));
    json glb = json::array();
    if (m.contains("gltf")) {
      glb.push_back(m["gltf"]["file"]);
      for (auto& n : m["gltf"]["warnings"])
        notes += (notes.empty() ? "" : "; ") + std::string("glTF: ") + escape(str(n));
    }
    p << row({escape(str(m["model"])), n4(m["alpha_u"]), n4(m["alpha_v"]), links(m["mitsuba"]),
              links(m["pbrt"]), links(glb), notes.empty() ? "none (the fit is a GGX)" : notes});
  }
  p << "</table>\n<p class=\"cap\">The measured (tabulated) BRDF as an RGL <code>.bsdf</code> "
       "table, for Mitsuba's and pbrt's <code>measured</code> material, is not written here (a "
       "fine anisotropic table takes minutes): from this folder, <code>"
    << escape(str(e["bsdf_command"]))
    << "</code>, then <code>microbrdf export mitsuba --bsdf measured.bsdf -o DIR</code> (or "
       "<code>pbrt</code>).</p>\n";
}

void section_brdf(Page& p, json& s) {
  json& b = s["brdf"];
  json& m = s["material"];
  p << "<h2 id=\"s5\">5. BRDF slices</h2>\n<p>Material: <b>" << escape(str(m["name"])) << "</b> ("
    << escape(str(m["source"])) << "), n = " << n4(m["n_555nm"]) << ", k = " << n4(m["k_555nm"])
    << " at 555 nm, normal-incidence reflectance " << n4(m["r0_555nm"])
    << " at 555 nm; colour under D65 <span class=\"swatch\" style=\"background:"
    << escape(str(m["srgb_hex"])) << "\"></span> " << escape(str(m["srgb_hex"]))
    << ". Slices at λ = " << len(b["wavelength_m"]) << "; "
    << escape(uncite(str(b["fresnel"]), m["source"], "")) << "; " << escape(str(b["shadowing"]))
    << ".</p>\n";
  p << "<table>\n<tr><th>model</th><th>description</th>";
  for (auto& a : b["albedo"])
    p << "<th>directional albedo, θi = " << report::num(d(a["theta_i_deg"])) << " deg</th>";
  p << "</tr>\n";
  for (auto& mod : b["models"]) {
    p << "<tr><td>" << escape(str(mod["label"])) << "</td><td>"
      << escape(uncite(str(mod["description"]), m["source"], "")) << "</td>";
    for (auto& a : b["albedo"])
      p << "<td class=\"n\">" << n4(a["albedo"][str(mod["key"])]) << "</td>";
    p << "</tr>\n";
  }
  p << "</table>\n<p class=\"cap\">Provenance: microfacet BRDF f = F D G / (4 |wi.n| |wo.n|) (Dong "
       "2015 eq. 1; Kirchhoff: eq. 8 with the ellipsoid fit's shadowing); directional albedo "
       "∫ f cos θo dω (dimensionless) by the BRDF's own sampler on a 128 &times; 128 stratified "
       "grid (<code>directional_albedo_sampled</code>). Light at azimuth 180 deg; in-plane "
       "angles signed, mirror at +θi.</p>\n";
  p << "<table>\n<tr><th>slice</th>";
  for (auto& mod : b["models"]) p << "<th>" << escape(str(mod["label"])) << ": peak</th>";
  p << "</tr>\n";
  for (auto& sl : b["slices"]) {
    p << "<tr><td>" << str(sl["plane"]) << "-plane, θi = " << report::num(d(sl["theta_i_deg"]))
      << " deg</td>";
    for (auto& mod : b["models"]) {
      json& pk = sl["peak"][str(mod["key"])];
      p << "<td class=\"n\">" << n4(pk["value_per_sr"]) << " 1/sr at "
        << report::num(d(pk["angle_deg"])) << " deg</td>";
    }
    p << "</tr>\n";
  }
  p << "</table>\n<div class=\"grid\">";
  for (auto& sl : b["slices"]) {
    if (!sl.contains("zoom")) {
      p << "<figure>" << p.svg(str(sl["plot"])) << "</figure>";
      continue;
    }
    // A narrow lobe: the zoomed companion plot beside the full one.
    json& z = sl["zoom"];
    p << "<figure class=\"zoomed\"><div class=\"zpair\"><div>" << p.svg(str(sl["plot"]))
      << "</div><div class=\"zoomp\">" << p.svg(str(z["plot"]))
      << "</div></div><figcaption>Right: zoom on the measured lobe, "
      << report::num(d(z["range_deg"][0]), 3) << " to " << report::num(d(z["range_deg"][1]), 3)
      << " deg (the same curves and colours; 3 decades).</figcaption></figure>";
  }
  p << "</div>\n";
}

// A colour bar from 0 to `top` x Y_99% (HTML: the text is real text).
std::string difference_bar(const json& scale) {
  return "<div class=\"cbar\" style=\"background:" + report::colour_gradient("to right") +
         "\"></div><div class=\"cbar-l\"><span>0</span><span>" + report::num(d(scale["max"]), 3) +
         " &times; Y<sub>99%</sub></span></div>";
}

std::string pct(const json& v) { return report::num(100 * d(v), 3) + " %"; }

// The NDF the measured renders use ("naive", "filtered" or "kirchhoff"; --render-ndf), for
// captions: "filtered NDF" unless the run chose another.
std::string render_ndf_label(const json& s) {
  if (s.contains("regime") && s["regime"].is_object() &&
      s["regime"].value("used", "") == "rayleigh-rice")
    return "Rayleigh-Rice BRDF of the scans' PSD";
  std::string k = "filtered";
  if (s.contains("ndf_comparison") && s["ndf_comparison"].is_object())
    k = s["ndf_comparison"].value("render_ndf", k);
  return k == "kirchhoff" ? "D_K" : k + " NDF";
}

// The table of contents' links into the renders section: the colour block and each scene of the
// comparison strip, only those this run made.
std::string toc_render_links(const json& s) {
  std::vector<std::string> links;
  bool colour = false;
  if (s.contains("renders") && s["renders"].is_array())
    for (auto& r : s["renders"]) {
      const std::string role = r.value("role", "");
      colour = colour || role == "studio" || role == "swatch";
    }
  if (colour) links.push_back("<a href=\"#colour\">the material's own colour</a>");
  if (s.contains("render_comparison") && s["render_comparison"].contains("scenes"))
    for (auto& sc : s["render_comparison"]["scenes"]) {
      const std::string scene = sc.value("scene", "");
      if (!scene.empty())
        links.push_back("<a href=\"#compare-" + escape(scene) + "\">each model: " + escape(scene) +
                        "</a>");
    }
  std::string out;
  for (auto& l : links) out += (out.empty() ? " (" : ", ") + l;
  return out.empty() ? out : out + ")";
}

const char* scene_title(const std::string& scene) {
  if (scene == "cylinders") return "the cylinder pair";
  if (scene == "sphere") return "the sphere";
  if (scene == "plate") return "the plate under a small light";
  return "the scene";
}

// One scene of the comparison strip: the measured-NDF render with each fit (and D_K) beside it,
// difference images on one colour scale, SSIM and RMS relative error, the render noise.
void comparison_scene(Page& p, json& rc, bool first, const std::string& ndf_label) {
  json& noise = rc["noise"];
  const std::string scene = str(rc["scene"]);
  const bool smooth = rc.contains("smoothing_sigma_px");
  const std::string sigma = smooth ? report::num(d(rc["smoothing_sigma_px"]), 2) : "";
  // Five figures per row at the page width; the strip shows half-size copies of large renders
  // (the full renders are linked).
  const int w = 232;
  const std::string fig = "<figure style=\"width:" + std::to_string(w) + "px;max-width:100%\">";
  auto shown = [&](json& e, const char* full, const char* half) {
    return e.contains(half) ? str(e[half]) : str(e[full]);
  };
  auto full_link = [&](json& e, const char* full, const char* half) {
    if (!e.contains(half)) return std::string();
    return " <a href=\"" + escape(str(e[full])) + "\">Full size (" +
           std::to_string(rc["width"].get<long>()) + " px).</a>";
  };
  p << "<h3 id=\"compare-" << escape(scene) << "\">Each model rendered: " << scene_title(scene)
    << "</h3>\n<p>";
  if (first)
    p << "The scene above rendered with each fitted NDF"
      << (rc["models"].size() > 3 ? " and the Kirchhoff D_K" : "")
      << " in place of the measured one: same lights, exposure, size, samples per pixel and "
         "seed. Under each, the difference of the linear luminance |Y<sub>model</sub> &minus; "
         "Y<sub>measured</sub>|"
      << (smooth ? ", both smoothed by a Gaussian of &sigma; = " + sigma +
                       " px (Monte Carlo noise is independent from pixel to pixel and averages "
                       "out; the models' differences are many pixels wide and stay)"
                 : std::string())
      << ", on one colour scale per scene, and numbers against the measured-NDF render: SSIM "
         "(Wang et al. 2004; 11 &times; 11 Gaussian windows, &sigma; = 1.5 px, on the displayed "
         "luminance, full resolution; 1 = identical) and the RMS relative error of the linear "
         "luminance (RMS of the difference / RMS of the measured render) per pixel"
      << (smooth ? " and after the smoothing" : "") << ". ";
  p << std::to_string(rc["width"].get<long>()) << " &times; "
    << std::to_string(rc["height"].get<long>()) << " px, " << std::to_string(rc["spp"].get<long>())
    << " samples/pixel, seed " << std::to_string(rc["seed"].get<long>()) << ", exposure "
    << report::num(d(rc["exposure_stops"]), 3) << " stops; lights: " << escape(str(rc["lights"]))
    << ".</p>\n<p><b>Render noise</b>: ";
  const bool halves = noise.contains("method") && str(noise["method"]) == "halves";
  if (first) {
    if (halves)
      p << "the renderer kept the images of the first and the second half of the measured-NDF "
           "render's samples apart; half their difference is one realisation of the image's "
           "own Monte Carlo noise (for the Sobol' sampler an upper estimate: the two halves of "
           "one sequence are slightly anti-correlated), so the noise is known without a second "
           "render. The noise of the image is ";
    else
      p << "the measured NDF rendered again with seed "
        << std::to_string(noise["second_seed"].get<long>())
        << " differs from the first by Monte Carlo noise alone; the noise of one image is ";
  } else {
    p << "one image, estimated as above: ";
  }
  p << pct(noise["rms_relative"]) << " RMS relative per pixel";
  if (smooth) p << " and " << pct(noise["rms_relative_smoothed"]) << " after the smoothing";
  if (first)
    p << ". Two independent renders would differ by &radic;2 times that (the row \"noise "
         "only\" below; its SSIM compares the render with itself plus that difference: "
      << report::num(d(noise["ssim_two_seeds"]), 4)
      << "). The models are rendered along the same paths as the reference (one render of "
         "all of them: shared camera rays, light samples and shadow rays, each direction drawn "
         "by one of their samplers and weighted for every model), so most of the noise cancels "
         "in their differences: what a model's numbers and difference image show is mostly the "
         "model's own departure from the measurement. A model at or below the noise-only row "
         "differs from the measurement by less than two independent renders of the measurement "
         "would.</p>\n<table>\n";
  else
    p << "; SSIM with noise only " << report::num(d(noise["ssim_two_seeds"]), 4)
      << ".</p>\n<table>\n";
  if (smooth)
    p << row({"model", "SSIM vs measured", "RMS relative error per pixel",
              "RMS relative error, smoothed (&sigma; = " + sigma + " px)"},
             true)
      << row({"measured, noise only (two independent renders)", n4(noise["ssim_two_seeds"]),
              report::num(100 * d(noise["rms_relative"]) * std::sqrt(2.0), 3) + " %",
              report::num(100 * d(noise["rms_relative_smoothed"]) * std::sqrt(2.0), 3) + " %"});
  else
    p << row({"model", "SSIM vs measured", "RMS relative error vs measured"}, true)
      << row({"measured, noise only (two independent renders)", n4(noise["ssim_two_seeds"]),
              report::num(100 * d(noise["rms_relative"]) * std::sqrt(2.0), 3) + " %"});
  for (auto& m : rc["models"]) {
    if (smooth)
      p << row({escape(str(m["label"])), n4(m["ssim"]), pct(m["rms_relative"]),
                pct(m["rms_relative_smoothed"])});
    else
      p << row({escape(str(m["label"])), n4(m["ssim"]), pct(m["rms_relative"])});
  }
  json& sc = rc["difference_scale"];
  p << "</table>\n";
  if (!(d(sc["reference_luminance"]) > 1e-9))
    p << "<p class=\"note\">The measured-NDF render is black: no facet of the measured NDF "
         "sends this scene's light into the camera (for the plate: facets tilted about 11.5 deg "
         "towards the light). The numbers compare black with the models.</p>\n";
  p << "<div class=\"grid\">" << fig
    << p.image(shown(rc, "reference", "reference_thumbnail"), "measured NDF, " + scene, w)
    << p.image(str(noise["difference_image"]), "noise difference", w) << difference_bar(sc)
    << "<figcaption>Measured (" << escape(ndf_label) << "): the reference."
    << full_link(rc, "reference", "reference_thumbnail")
    << " Below: noise alone, |&Delta;Y| that two independent renders of it would show, on the "
       "scale of the models' difference images.</figcaption></figure>";
  for (auto& m : rc["models"]) {
    p << fig << p.image(shown(m, "image", "thumbnail"), str(m["label"]) + ", " + scene, w)
      << p.image(str(m["difference_image"]), str(m["label"]) + " difference", w)
      << difference_bar(sc) << "<figcaption>" << escape(str(m["label"])) << ": SSIM "
      << n4(m["ssim"]) << ", RMS relative error " << pct(m["rms_relative"]);
    if (smooth) p << " (" << pct(m["rms_relative_smoothed"]) << " smoothed)";
    p << "." << full_link(m, "image", "thumbnail")
      << " Below: |&Delta;Y| against the measured render, in units of its 99th-percentile "
         "luminance Y<sub>99%</sub> = "
      << report::num(d(sc["reference_luminance"]), 3) << " (linear sRGB).</figcaption></figure>";
  }
  if (rc.contains("multiple_scattering") && rc["multiple_scattering"].is_object()) {
    json& ms = rc["multiple_scattering"];
    p << fig << p.image(str(ms["difference_image"]), "multiple against single scattering", w)
      << difference_bar(ms.contains("difference_scale") ? ms["difference_scale"] : sc)
      << "<figcaption>Multiple against single scattering on the same NDF: |&Delta;Y| between "
         "the two renders, the light the single-scattering BRDF drops, on its own scale (full "
         "colour "
      << report::num(d(ms.contains("difference_scale") ? ms["difference_scale"]["max"] : sc["max"]),
                     3)
      << " Y<sub>99%</sub>; the models' scale: " << report::num(d(sc["max"]), 3)
      << "). Mean luminance, multiple / single: " << report::num(d(ms["mean_luminance_ratio"]), 4)
      << ".</figcaption></figure>";
  }
  p << "</div>\n";
}

// The comparison strip under the renders: one block per scene ("scenes"; a summary from before
// the other scenes has the cylinder pair's keys at the top level only).
void comparison_strip(Page& p, json& s) {
  if (!s.contains("render_comparison")) return;
  json& rc = s["render_comparison"];
  if (rc.contains("scenes") && rc["scenes"].is_array() && !rc["scenes"].empty()) {
    bool first = true;
    for (auto& scene : rc["scenes"])
      comparison_scene(p, scene, std::exchange(first, false), render_ndf_label(s));
  } else {
    comparison_scene(p, rc, true, render_ndf_label(s));
  }
}

// A render's figure: image, caption with its settings.
void render_figure(Page& p, json& s, json& im, int shown_width, const std::string& extra,
                   bool brief = false) {
  const std::string material =
      uncite(str(im["material"]), s["material"]["source"], " (optical constants of section 5)");
  p << "<figure style=\"width:" << std::to_string(shown_width) << "px;max-width:100%\">"
    << p.image(str(im["file"]), str(im["scene"]), shown_width) << "<figcaption>"
    << escape(str(im["caption"])) << ". " << extra << std::to_string(im["width"].get<long>())
    << " &times; " << std::to_string(im["height"].get<long>()) << " px, "
    << std::to_string(im["spp"].get<long>()) << " samples/pixel, path depth &le; "
    << std::to_string(im["max_depth"].get<long>()) << ", seed "
    << std::to_string(im["seed"].get<long>());
  if (im.contains("exposure_stops"))
    p << ", exposure " << report::num(d(im["exposure_stops"]), 3) << " stops";
  if (brief) {
    p << ".</figcaption></figure>";
    return;
  }
  p << "; lights: " << escape(str(im["lights"])) << ". Material: " << escape(material)
    << ".</figcaption></figure>";
}

void section_renders(Page& p, json& s) {
  p << "<h2 id=\"s6\">6. Renders</h2>\n";
  json& r = s["renders"];
  if (r.is_object() && r.contains("skipped")) {
    p << "<p class=\"note\">" << escape(str(r["skipped"])) << "</p>\n";
    {
      const auto g = report::gltf_view_html(s, p.path(""));
      p << report::material_view_html(s, g.beside, g.after);
    }
    return;
  }
  const double smooth_deg = d(s["ndf"]["filtered"]["smooth_axis_angle_rad"]) * kDeg;
  auto role = [](json& im) { return im.contains("role") ? str(im["role"]) : std::string("scene"); };
  p << "<div class=\"grid\">";
  for (auto& im : r) {
    if (role(im) != "scene") continue;
    std::string which;
    if (str(im["scene"]) == "cylinders" && std::isfinite(smooth_deg)) {
      // Linear brushing: the scan's x axis along the camera's right on the left cylinder,
      // turned 90 degrees on the right one; scratches run along the smooth axis.
      const bool horizontal = std::fabs(std::remainder(smooth_deg, 180.0)) < 45;
      which = std::string(
                  "Left cylinder: the scan's x axis horizontal, its scratches (smooth "
                  "axis at ") +
              report::num(smooth_deg, 3) + " deg from x) run " +
              (horizontal ? "around the cylinder" : "along the cylinder's axis") +
              "; right cylinder: turned 90 deg, scratches " +
              (horizontal ? "along the axis" : "around the cylinder") + ". ";
    }
    render_figure(p, s, im, std::clamp(im["width"].get<int>(), 384, 400), which);
  }
  p << "</div>\n<p class=\"cap\">Provenance: the spectral path tracer (<code>render</code>, "
       "Embree 3), linear sRGB tone-mapped to 8-bit sRGB at the exposure given (chosen per "
       "scene so that the measured render's 99th-percentile luminance shows at about full "
       "white; the models of the comparison strip below use the same); the BRDF is the measured "
       "one ("
    << escape(render_ndf_label(s))
    << " as a tabulated distribution with Smith shadowing, exact conductor Fresnel).</p>\n";
  // The material's own colour: the neutral studio map and a swatch on white.
  bool any = false;
  for (auto& im : r) any = any || role(im) == "studio" || role(im) == "swatch";
  if (any) {
    json& m = s["material"];
    p << "<h3 id=\"colour\">The material's own colour</h3>\n<p>A warm environment tints a "
         "metal (under the courtyard, grey steel can look like bronze). Below: the same "
         "measured BRDF under a neutral studio map (grey surroundings, two white softboxes), "
         "and on white.</p>\n<div class=\"grid\">";
    for (auto& im : r)
      if (role(im) == "studio")
        render_figure(p, s, im, 300, "Lights: " + escape(str(im["lights"])) + ". ", true);
    for (auto& im : r)
      if (role(im) == "swatch") render_figure(p, s, im, 160, "", true);
    p << "<figure style=\"width:160px\"><div style=\"width:150px;height:96px;border:1px solid "
         "#888;background:"
      << escape(str(m["srgb_hex"]))
      << "\"></div><figcaption>Flat patch: normal-incidence reflectance R(0) of "
      << escape(str(m["name"])) << " under D65, as sRGB " << escape(str(m["srgb_hex"]))
      << " (section 5).</figcaption></figure></div>\n";
  }
  comparison_strip(p, s);
  {
    const auto g = report::gltf_view_html(s, p.path(""));
    p << report::material_view_html(s, g.beside, g.after);
  }
}

void texture_block(Page& p, json& t, const char* title) {
  p << "<h3>" << title << ": " << std::to_string(t["nx"].get<long>()) << " &times; "
    << std::to_string(t["ny"].get<long>()) << " texels of " << len(t["texel_m"]) << ", "
    << std::to_string(t["invalid_texels"].get<long>()) << " invalid"
    << (t.contains("alpha_zoomed")
            ? ", " + std::to_string(t["alpha_zoomed"].get<long>()) +
                  " narrow widths refitted on zoomed tables, " +
                  std::to_string(t.value("alpha_lifted_to_min", 0L)) + " lifted to alpha 1e-5"
            : "")
    << "</h3>\n<table>\n"
    << row({"channel", "unit", "mean", "std", "min", "max"}, true);
  for (auto& [ch, st] : t["channels"].items()) {
    const bool angle = ch.rfind("theta", 0) == 0;
    if (!st.contains("mean")) {
      p << row({ch, angle ? "deg" : "1", "no valid texel", "—", "—", "—"});
      continue;
    }
    const double k = angle ? kDeg : 1.0;
    p << row({ch, angle ? "deg" : "1", report::num(d(st["mean"]) * k),
              report::num(d(st["std"]) * k), report::num(d(st["min"]) * k),
              report::num(d(st["max"]) * k)});
  }
  p << "</table>\n";
  if (t.contains("images")) {
    p << "<div class=\"grid\">";
    for (auto& [ch, file] : t["images"].items()) {
      // A colour bar from the channel's min to max (the range the image maps), in its unit.
      json& st = t["channels"][ch];
      const bool angle = ch.rfind("theta", 0) == 0;
      const double k = angle ? kDeg : 1.0;
      const std::string unit = angle ? " deg" : "";
      p << "<figure class=\"tex\">" << p.image(str(file), ch)
        << "<div class=\"cbar\" style=\"background:" << report::colour_gradient("to right")
        << "\"></div><div class=\"cbar-l\"><span>" << report::num(d(st["min"]) * k) << unit
        << "</span><span>" << report::num(d(st["max"]) * k) << unit << "</span></div><figcaption>"
        << ch << " (false colour, min to max of the table above)</figcaption></figure>";
    }
    p << "</div>\n";
  }
}

void section_texture(Page& p, json& s) {
  p << "<h2 id=\"s7\">7. Texture synthesis</h2>\n";
  json& t = s["texture"];
  if (t.contains("skipped")) {
    p << "<p class=\"note\">" << escape(str(t["skipped"])) << "</p>\n";
    return;
  }
  p << "<p>Per-texel ellipsoid fits of filtered NDFs of texels " << len(t["texel_m"])
    << " wide, separable spectrum synthesis (Dong 2015 sec. 9), seed "
    << std::to_string(t["seed"].get<long>()) << "; parameter texture in <code>"
    << escape(str(t["file"])) << "</code>";
  if (t.contains("gltf"))
    p << "; as glTF 2.0 (a spatially varying <code>KHR_materials_anisotropy</code> on a sphere "
         "and a plate, for real-time viewers, docs/gltf.md): <a href=\""
      << escape(str(t["gltf"]["file"])) << "\"><code>" << escape(str(t["gltf"]["file"]))
      << "</code></a>";
  p << ".</p>\n";
  texture_block(p, t["along"], "Exemplar strip along the brushing");
  texture_block(p, t["across"], "Exemplar strip across the brushing");
  texture_block(p, t["synthesised"], "Synthesised texture");
  if (t.contains("render"))
    p << "<figure>"
      << p.image(str(t["render"]["file"]), "textured cylinders",
                 std::max(384, t["render"]["width"].get<int>()))
      << "<figcaption>The synthesised SVBRDF (ellipsoid NDF per texel, exact Fresnel) on the "
         "cylinder pair, a scene unit read as 5 cm (the texture repeats "
      << report::num(d(t["render"]["uv_scale"])) << " times per unit); "
      << std::to_string(t["render"]["spp"].get<long>())
      << " samples/pixel; lights: " << escape(str(t["render"]["lights"]))
      << ".</figcaption></figure>\n";
}

void section_settings(Page& p, json& s) {
  p << "<h2 id=\"s8\">8. Settings and versions</h2>\n<table>\n" << row({"setting", "value"}, true);
  for (auto& [k, v] : s["settings"].items()) {
    std::string text;
    if (v.is_number_float()) {
      const bool metres = k.size() > 2 && k.substr(k.size() - 2) == "_m";
      text = metres ? report::length(d(v)) : report::num(d(v));
    } else if (k == "slice_theta_i_rad") {
      for (auto& t : v) text += (text.empty() ? "" : ", ") + report::num(d(t) * kDeg) + " deg";
    } else if (k == "kirchhoff_patch_m") {
      text = len(v[0]) + " &times; " + len(v[1]);
    } else if (k == "spacing_override_m") {
      auto one = [](json& x) { return x.is_number() ? len(x) : escape(str(x)); };
      text = "dx " + one(v[0]) + ", dy " + one(v[1]);
    } else if (v.is_array()) {
      for (auto& x : v) text += (text.empty() ? "" : ", ") + escape(str(x));
      if (text.empty()) text = "none";
    } else if (k == "optical_constants" && v.is_object()) {
      text = escape(str(v["name"])) + " (source cited in section 5)";  // each citation once
    } else if (v.is_object()) {
      for (auto& [kk, x] : v.items())
        text += (text.empty() ? "" : "; ") + escape(kk) + ": " + escape(str(x));
    } else if (v.is_boolean()) {
      text = v.get<bool>() ? "yes" : "no";
    } else {
      text = escape(str(v));
    }
    // The key without its unit suffix: the value carries the unit it is shown in.
    std::string name = k;
    for (const char* suffix : {"_rad", "_m"}) {
      const std::string sfx = suffix;
      if (name.size() > sfx.size() &&
          name.compare(name.size() - sfx.size(), sfx.size(), sfx) == 0) {
        name.resize(name.size() - sfx.size());
        break;
      }
    }
    p << row({escape(name), text});
  }
  p << "</table>\n<table>\n" << row({"component", "version"}, true);
  for (auto& [k, v] : s["versions"].items()) p << row({escape(k), escape(str(v))});
  p << "</table>\n";
}

void section_timing(Page& p, json& s) {
  p << "<h2 id=\"s9\">9. Timings</h2>\n<table>\n" << row({"step", "wall time or rate"}, true);
  auto ends = [](const std::string& k, const std::string& sfx) {
    return k.size() > sfx.size() && k.compare(k.size() - sfx.size(), sfx.size(), sfx) == 0;
  };
  for (auto& [k, v] : s["timing"].items()) {
    if (ends(k, "_samples_per_s"))
      p << row(
          {escape(k.substr(0, k.size() - 14)) + " (rate)", report::num(d(v), 4) + " samples/s"});
    else if (ends(k, "_per_s"))
      p << row({escape(k.substr(0, k.size() - 6)) + " (rate)", report::num(d(v), 4) + " /s"});
    else if (ends(k, "_s"))
      p << row({escape(k.substr(0, k.size() - 2)), report::num(d(v), 3) + " s"});
    else
      p << row({escape(k), report::num(d(v), 3)});
  }
  p << "</table>\n<p class=\"cap\">Wall-clock seconds (and path samples per second for the "
       "renders) on this machine: the only numbers that change between identical runs.</p>\n<h2 "
       "id=\"s10\">10. Files in this folder</h2>\n<p>";
  // Relative links: they open the files beside report.html (nothing leaves the folder).
  for (auto& f : s["outputs"])
    p << "<a href=\"" << escape(str(f)) << "\"><code>" << escape(str(f)) << "</code></a> ";
  p << "</p>\n";
}

}  // namespace

std::string render_report_html(const json& summary, const std::string& dir) {
  // A mutable copy: the sections index it with operator[], which on a const json is undefined
  // behaviour for a missing key (ASan found one); on a mutable one it yields null, which the
  // formatters print as a dash and scripts/check-report.py flags.
  json s = summary;
  Page p(dir);
  p << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
       "<title>microbrdf predict report</title>\n<style>"
    << kStyle << "</style></head>\n<body>\n<h1>microbrdf predict report</h1>\n";
  warnings_box(p, s);
  json& f = s["ndf"]["filtered"];
  // The best fit that is not poor (good before usable, then the lower Hellinger distance), or
  // the measured table when every fit is poor: the line never quotes a model the warnings say
  // not to use.
  json* best = nullptr;
  auto rank = [](json& fit) { return str(fit["verdict"]) == "good" ? 0 : 1; };
  for (auto& fit : s["fits"])
    if (str(fit["verdict"]) != "poor" &&
        (!best || rank(fit) < rank(*best) ||
         (rank(fit) == rank(*best) && d(fit["hellinger"]) < d((*best)["hellinger"]))))
      best = &fit;
  const std::string fit_line =
      best ? "best fit " + escape(str((*best)["model"])) + " (" + str((*best)["verdict"]) +
                 ") alpha_x " + n4((*best)["params"]["alpha_x"]) + ", alpha_y " +
                 n4((*best)["params"]["alpha_y"])
           : "no parametric model fits this NDF (every fit is poor, section 4): use the "
             "measured table, <code>ndf_filtered.npy</code>";
  p << "<p>" << std::to_string(s["inputs"].size()) << " scan(s); metal "
    << escape(str(s["material"]["name"])) << "; filtered NDF (filter sigma "
    << len(s["settings"]["filter_sigma_m"]) << ") rms slopes " << n4(f["slope_rms_x"])
    << " along x and " << n4(f["slope_rms_y"]) << " along y (anisotropy " << n4(f["anisotropy"])
    << ", smooth axis at " << report::num(d(f["smooth_axis_angle_rad"]) * kDeg) << " deg from +x); "
    << fit_line
    << ". Every number below is in <code>summary.json</code> (SI units; docs/report.md).</p>\n";
  p << "<nav class=\"toc\"><b>Contents</b><ol><li><a href=\"#warnings\">Warnings</a> ("
    << std::to_string(s["warnings"].is_array() ? s["warnings"].size() : 0) << ")</li>"
    << "<li><a href=\"#s1\">Inputs</a></li>"
       "<li><a href=\"#s2\">Surface statistics</a></li><li><a href=\"#s3\">Normal "
       "distribution functions</a></li><li><a href=\"#s4\">Parametric fits</a></li><li><a "
       "href=\"#s5\">BRDF slices</a></li><li><a href=\"#s6\">Renders</a>"
    << toc_render_links(s)
    << " and the <a href=\"#view\">interactive view</a></li><li><a href=\"#s7\">Texture "
       "synthesis</a></li>";
  if (s.contains("measured") && s["measured"].is_object())
    p << "<li><a href=\"#s-measured\">Prediction against the measurement</a></li>";
  p << "<li><a href=\"#s8\">Settings and versions</a></li><li><a href=\"#s9\">Timings</a></li>"
       "<li><a href=\"#s10\">Files</a></li></ol></nav>\n";
  section_inputs(p, s);
  section_stats(p, s);
  p << report::regime_section_html(s, dir);
  section_ndf(p, s);
  p << report::ndf_comparison_html(s, dir);
  section_fits(p, s);
  section_brdf(p, s);
  p << report::energy_loss_html(s);
  section_renders(p, s);
  section_texture(p, s);
  p << report::measured_section_html(s, dir);
  section_settings(p, s);
  section_timing(p, s);
  p << "</body></html>\n";
  return p.str();
}

}  // namespace microbrdf
