// `predict --measured`: the comparison stage and its report section (predict_measured.hpp).
#include "report/predict_measured.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <memory>

#include "microbrdf/error.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/measured.hpp"
#include "microbrdf/measured_compare.hpp"
#include "microbrdf/measured_ndf.hpp"
#include "microbrdf/ndf_io.hpp"
#include "report/html.hpp"

namespace microbrdf::report {
namespace {

namespace fs = std::filesystem;
constexpr double kDegPerRad = 180.0 / 3.14159265358979323846;

std::string lower_extension(const std::string& path) {
  std::string e = fs::path(path).extension().string();
  for (auto& ch : e) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return e;
}

bool is_table(const std::string& path) {
  const std::string e = lower_extension(path);
  return e == ".npy" || e == ".exr";
}

std::string cell(const nlohmann::json& v) { return num_or(v, "&mdash;"); }

}  // namespace

void check_measured_option(const PredictOptions& o) {
  if (o.measured_path.empty()) return;
  if (!fs::exists(o.measured_path)) throw FileError::missing(o.measured_path, "--measured");
  if (!(o.instrument_fwhm_rad >= 0 && o.instrument_fwhm_rad < 0.35))
    throw InputError("instrument FWHM must lie in [0, 20) deg");
  if (!o.instrument_path.empty()) {
    if (o.instrument_fwhm_rad > 0)
      throw InputError("give --instrument-fwhm or --instrument, not both");
    if (!fs::exists(o.instrument_path)) throw FileError::missing(o.instrument_path, "--instrument");
    (void)read_ndf(o.instrument_path);
  }
  // Read it now (cheap next to the pipeline): a broken file fails before the scans are read.
  const std::string e = lower_extension(o.measured_path);
  if (is_table(o.measured_path))
    (void)read_ndf(o.measured_path);
  else if (e == ".csv")
    (void)read_gonio_csv(o.measured_path);
  else if (e == ".binary" || e == ".bsdf")
    (void)read_measured_brdf(o.measured_path);
  else
    throw InputError(o.measured_path +
                     ": --measured takes a goniometer .csv, a MERL .binary, an RGL .bsdf or an "
                     "effective NDF table (.npy/.exr from `measured ndf`)");
}

nlohmann::json stage_measured(const Context& c, const NdfSet& ndfs) {
  const PredictOptions& o = c.opt;
  c.log("measured: " + o.measured_path);
  EffectiveNdfOptions eo;
  eo.resolution = std::min<std::size_t>(o.ndf_resolution, 513);
  eo.wavelength_m = o.wavelength_m;
  TabulatedNdf measured = is_table(o.measured_path)
                              ? read_ndf(o.measured_path)
                              : measured_ndf_file(o.measured_path, PerfectMirrorFresnel(), eo);
  if (!is_table(o.measured_path))
    if (const std::string w = wavelength_warning(measured, eo.wavelength_m, o.measured_path);
        !w.empty())
      c.warn("measured_wavelength", w,
             "the measured NDF is compared as it is; give a file measured at the prediction's "
             "wavelength, or predict at the measured one (--wavelength)");
  write_ndf(measured, c.path("ndf_measured.npy"));
  nlohmann::json out = {{"file", o.measured_path},
                        {"table", "ndf_measured.npy"},
                        {"resolution", measured.resolution()},
                        {"measured_nodes", measured_nodes(measured)},
                        {"notes", measured.meta.notes},
                        {"instrument_fwhm_rad", o.instrument_fwhm_rad},
                        {"instrument", o.instrument_path.empty() ? "none" : o.instrument_path}};
  if (!is_table(o.measured_path)) out["theta_d_rad"] = eo.theta_d;
  std::unique_ptr<TabulatedNdf> sig;
  if (!o.instrument_path.empty()) sig = std::make_unique<TabulatedNdf>(read_ndf(o.instrument_path));
  nlohmann::json all = nlohmann::json::array();
  const std::pair<const char*, const TabulatedNdf*> predictions[] = {
      {"filtered", ndfs.filtered.get()}, {"kirchhoff", ndfs.kirchhoff.get()}};
  for (const auto& [name, table_ptr] : predictions) {
    const TabulatedNdf* table = table_ptr;  // a plain variable: clang 14 cannot capture bindings
    if (!table) continue;
    const NdfComparison cmp = about_file(o.measured_path, [&] {
      return compare_ndfs(measured, *table, o.instrument_fwhm_rad, sig.get());
    });
    const std::string rel = std::string("measured/") + name;
    write_compare_report(
        measured, instrument_view(*table, measured.resolution(), o.instrument_fwhm_rad, sig.get()),
        cmp, c.path(rel));
    nlohmann::json j = comparison_json(cmp);
    j["prediction"] = name;
    j["images"] = {{"measured", rel + "/measured.png"},
                   {"predicted", rel + "/predicted.png"},
                   {"slices", rel + "/slices.png"}};
    j["slices_csv"] = rel + "/slices.csv";
    all.push_back(std::move(j));
  }
  out["comparisons"] = std::move(all);
  return out;
}

std::string measured_section_html(const nlohmann::json& summary, const std::string& dir) {
  if (!summary.contains("measured") || !summary["measured"].is_object()) return "";
  const nlohmann::json& m = summary["measured"];
  const auto img = [&](const nlohmann::json& rel, const std::string& alt) {
    return "<img src=\"" +
           data_uri((fs::path(dir) / rel.get<std::string>()).string(), "image/png") + "\" alt=\"" +
           escape(alt) + "\">";
  };
  const double fwhm = m.value("instrument_fwhm_rad", 0.0);
  std::string h =
      "<h2 id=\"s-measured\">Prediction against the measurement</h2>\n<p>Measured: <code>" +
      escape(m.value("file", "")) +
      "</code>, effective NDF (Dong eq. 9, G = 1, F = 1: "
      "the shape) on " +
      std::to_string(m.value("resolution", 0)) + "&sup2; nodes, " +
      std::to_string(m.value("measured_nodes", 0)) +
      " of them measured (the rest unmeasured, shown grey, never compared)";
  if (m.contains("theta_d_rad"))
    h += "; read at &theta;<sub>d</sub> = " + num(m["theta_d_rad"].get<double>() * kDegPerRad) +
         " deg";
  const std::string sig = m.value("instrument", "");
  h += ". Instrument: " +
       (!sig.empty() && sig != "none"
            ? "measured signature <code>" + escape(sig) + "</code> applied to the prediction"
        : fwhm > 0 ? "Gaussian of FWHM " + num(fwhm * kDegPerRad) + " deg applied to the prediction"
                   : std::string("none applied (<code>--instrument-fwhm</code> sets one)")) +
       ".</p>\n<table>\n<tr><th>prediction</th><th>measured nodes</th><th>scale</th>"
       "<th>relative L2</th><th>Hellinger</th><th>&alpha;<sub>x</sub> predicted / measured</th>"
       "<th>&alpha;<sub>y</sub> predicted / measured</th></tr>\n";
  for (const auto& c : m["comparisons"])
    h += "<tr><td>" + escape(c.value("prediction", "")) + "</td><td class=\"n\">" +
         std::to_string(c.value("nodes", 0)) + "</td><td class=\"n\">" + cell(c["scale"]) +
         "</td><td class=\"n\">" + cell(c["relative_l2"]) + "</td><td class=\"n\">" +
         cell(c["hellinger"]) + "</td><td class=\"n\">" + cell(c["alpha_x_ratio"]) +
         "</td><td class=\"n\">" + cell(c["alpha_y_ratio"]) + "</td></tr>\n";
  h += "</table>\n";
  for (const auto& c : m["comparisons"]) {
    const std::string name = c.value("prediction", "");
    h += "<h3>" + escape(name) + " NDF against the measurement</h3>\n<div class=\"grid\">";
    h += "<figure>" + img(c["images"]["measured"], "measured effective NDF") +
         "<figcaption>Measured (one colour scale with the prediction).</figcaption></figure>";
    h += "<figure>" + img(c["images"]["predicted"], "predicted NDF") + "<figcaption>Predicted (" +
         escape(name) +
         "), instrument applied, scaled by the least-squares factor.</figcaption></figure>";
    h += "<figure>" + img(c["images"]["slices"], "cuts") +
         "<figcaption>Cuts along and across the measured GGX fit's &alpha;<sub>x</sub> axis "
         "(Dong Fig. 9 layout); the numbers are in <code>" +
         escape(c.value("slices_csv", "")) + "</code>.</figcaption></figure></div>\n";
  }
  h += "<p class=\"cap\">Errors on the measured nodes only: relative L2 = ||M &minus; kP|| / "
       "||M||; Hellinger distance of the two, each normalised on those nodes; width ratios from "
       "GGX fits of both tables (docs/measured.md).</p>\n";
  return h;
}

}  // namespace microbrdf::report
