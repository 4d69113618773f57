// Predicted against measured effective NDFs (include/microbrdf/measured_compare.hpp).
#include "microbrdf/measured_compare.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>

#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/ndf_convolve.hpp"
#include "microbrdf/ndf_io.hpp"
#include "microbrdf/ndf_preview.hpp"
#include "microbrdf/plot.hpp"

namespace microbrdf {

TabulatedNdf instrument_view(const TabulatedNdf& predicted, std::size_t resolution, double fwhm,
                             const TabulatedNdf* instrument) {
  TabulatedNdf filled = predicted;  // a prediction with unmeasured (NaN) nodes: treat as 0
  for (double& v : filled.values())
    if (std::isnan(v)) v = 0;
  TabulatedNdf p = instrument ? convolve_signature(filled, *instrument)
                              : convolve_angular_gaussian(filled, fwhm);
  TabulatedNdf out(resolution);
  for (std::size_t iy = 0; iy < resolution; ++iy)
    for (std::size_t ix = 0; ix < resolution; ++ix)
      out.at(ix, iy) = p.eval_disk(out.node_x(ix), out.node_y(iy));
  out.meta = p.meta;
  return out;
}

NdfComparison compare_ndfs(const TabulatedNdf& measured, const TabulatedNdf& predicted, double fwhm,
                           const TabulatedNdf* instrument) {
  const std::size_t n = measured.resolution();
  const TabulatedNdf p = instrument_view(predicted, n, fwhm, instrument);
  NdfComparison r;
  double mp = 0, pp = 0, mm = 0, msum = 0, psum = 0;
  for (std::size_t iy = 0; iy < n; ++iy)
    for (std::size_t ix = 0; ix < n; ++ix) {
      const double x = measured.node_x(ix), y = measured.node_y(iy);
      const double m = measured.at(ix, iy);
      if (x * x + y * y >= 1 || !std::isfinite(m)) continue;
      const double v = p.at(ix, iy);
      mp += m * v;
      pp += v * v;
      mm += m * m;
      msum += std::max(m, 0.0);
      psum += std::max(v, 0.0);
      ++r.nodes;
    }
  if (r.nodes == 0 || !(mm > 0)) throw InputError("the measured table has no measured node");
  r.scale = pp > 0 ? mp / pp : 0;
  double e2 = 0, h2 = 0;
  for (std::size_t iy = 0; iy < n; ++iy)
    for (std::size_t ix = 0; ix < n; ++ix) {
      const double x = measured.node_x(ix), y = measured.node_y(iy);
      const double m = measured.at(ix, iy);
      if (x * x + y * y >= 1 || !std::isfinite(m)) continue;
      const double v = p.at(ix, iy);
      e2 += (m - r.scale * v) * (m - r.scale * v);
      if (msum > 0 && psum > 0) {
        const double d = std::sqrt(std::max(m, 0.0) / msum) - std::sqrt(std::max(v, 0.0) / psum);
        h2 += d * d;
      }
    }
  r.relative_l2 = std::sqrt(e2 / mm);
  r.hellinger = std::sqrt(0.5 * h2);
  FitOptions fo;
  fo.model = "ggx";
  r.measured_fit = fit_ndf(measured, fo);
  r.predicted_fit = fit_ndf(p, fo);
  r.alpha_x_ratio = r.predicted_fit.params.at("alpha_x") / r.measured_fit.params.at("alpha_x");
  r.alpha_y_ratio = r.predicted_fit.params.at("alpha_y") / r.measured_fit.params.at("alpha_y");
  return r;
}

nlohmann::json comparison_json(const NdfComparison& c) {
  return {{"nodes", c.nodes},
          {"scale", c.scale},
          {"relative_l2", c.relative_l2},
          {"hellinger", c.hellinger},
          {"alpha_x_ratio", c.alpha_x_ratio},
          {"alpha_y_ratio", c.alpha_y_ratio},
          {"measured_fit", fit_result_json(c.measured_fit)},
          {"predicted_fit", fit_result_json(c.predicted_fit)}};
}

void write_compare_report(const TabulatedNdf& measured, const TabulatedNdf& predicted_view,
                          const NdfComparison& c, const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) throw FileError(dir, "cannot create the report directory");
  const auto path = [&](const char* name) { return (fs::path(dir) / name).string(); };
  write_file_atomic(path("compare.json"), comparison_json(c).dump(2) + "\n");
  // One colour scale: the measured maximum; the prediction at the fitted scale.
  double vmax = 0;
  for (double v : measured.values())
    if (v > vmax) vmax = v;
  TabulatedNdf scaled = predicted_view;
  for (double& v : scaled.values()) v *= c.scale;
  NdfPreviewOptions po;
  po.zoom = true;
  po.max_value = vmax;
  po.title = "measured (grey: unmeasured)";
  write_ndf_preview(measured, path("measured.png"), po);
  po.title = fmt::format("predicted x {:.3g} (instrument applied)", c.scale);
  write_ndf_preview(scaled, path("predicted.png"), po);
  // Cuts along and across the measured fit's alpha_x axis.
  const double phi = c.measured_fit.phi;
  std::string csv = "cut,theta_deg,measured_per_sr,predicted_per_sr\n";
  std::vector<Plot> plots;
  for (int k = 0; k < 2; ++k) {
    const double a = phi + (k == 0 ? 0.0 : 3.14159265358979323846 / 2);
    const NdfSlice sm = measured.slice(a, 401), sp = scaled.slice(a, 401);
    const char* name = k == 0 ? "along" : "cross";
    Plot p;
    p.title = fmt::format("{} the alpha_x axis ({:.1f} deg)", k == 0 ? "along" : "across",
                          a * 180 / 3.14159265358979323846);
    p.x.label = "signed polar angle of m (deg)";
    p.y.label = "D (1/sr)";
    std::vector<double> xm, ym, xp, yp;
    for (std::size_t i = 0; i < sm.t.size(); ++i) {
      const double th = sm.theta[i] * 180 / 3.14159265358979323846;
      csv += fmt::format("{},{:.6g},{},{:.9g}\n", name, th,
                         std::isfinite(sm.value[i]) ? fmt::format("{:.9g}", sm.value[i]) : "",
                         sp.value[i]);
      if (std::isfinite(sm.value[i])) {
        xm.push_back(th);
        ym.push_back(sm.value[i]);
      }
      xp.push_back(th);
      yp.push_back(sp.value[i]);
    }
    p.add(PlotSeries(xp, yp, "predicted", PlotStyle::Line));
    if (!xm.empty()) p.add(PlotSeries(xm, ym, "measured", PlotStyle::Markers));
    plots.push_back(std::move(p));
  }
  write_file_atomic(path("slices.csv"), csv);
  write_plot_grid(plots, 2, path("slices.png"), 640, 440);
}

}  // namespace microbrdf
