// Fit report: JSON, measured | fit | residual images, slices (see fit.hpp).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "core/bitmap_font.hpp"
#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/fit.hpp"
#include "microbrdf/image.hpp"
#include "microbrdf/ndf_preview.hpp"
#include "microbrdf/plot.hpp"

namespace microbrdf {
namespace {

constexpr double kPi = 3.14159265358979323846;

void diverging(double t, std::uint8_t rgb[3]) {
  // t in [-1, 1]: blue - white - red.
  t = std::clamp(t, -1.0, 1.0);
  const double a = std::abs(t);
  const double r = t > 0 ? 1.0 : 1.0 - 0.8 * a, g = 1.0 - 0.8 * a, b = t < 0 ? 1.0 : 1.0 - 0.8 * a;
  rgb[0] = static_cast<std::uint8_t>(255 * r);
  rgb[1] = static_cast<std::uint8_t>(255 * g);
  rgb[2] = static_cast<std::uint8_t>(255 * b);
}

}  // namespace

void write_fit_report(const TabulatedNdf& ndf, const FitResult& r, const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw FileError(dir, "cannot create report directory: " + ec.message());
  const std::size_t n = ndf.resolution();
  const TabulatedNdf m = fit_table(r, n);

  {
    AtomicFile f(dir + "/fit.json");
    std::ofstream out(f.temp_path());
    out << fit_result_json(r).dump(2) << "\n";
    if (!out) throw FileError(dir + "/fit.json", "cannot write");
    out.close();
    f.commit();
  }

  // compare.png: three square panels over the region of interest (made square, >= 16 nodes).
  const double cx = 0.5 * (ndf.node_x(r.roi[0]) + ndf.node_x(r.roi[1]));
  const double cy = 0.5 * (ndf.node_y(r.roi[2]) + ndf.node_y(r.roi[3]));
  double half = 0.5 * std::max(ndf.node_x(r.roi[1]) - ndf.node_x(r.roi[0]),
                               ndf.node_y(r.roi[3]) - ndf.node_y(r.roi[2]));
  half = std::clamp(half, 8 * ndf.spacing(), 1.0);
  const std::size_t panel = 320, gap = 10, label_h = 24;
  RgbImage img(3 * panel + 4 * gap, panel + 2 * gap + label_h);
  std::fill(img.pixels.begin(), img.pixels.end(), std::uint8_t{255});
  double vmax = 0, rmax = 0;
  for (double v : ndf.values()) vmax = std::max(vmax, v);
  std::vector<double> res(panel * panel);
  for (std::size_t py = 0; py < panel; ++py)
    for (std::size_t px = 0; px < panel; ++px) {
      const double x = cx - half + 2 * half * (static_cast<double>(px) + 0.5) / panel;
      const double y = cy + half - 2 * half * (static_cast<double>(py) + 0.5) / panel;
      res[py * panel + px] = m.eval_disk(x, y) - ndf.eval_disk(x, y);
      rmax = std::max(rmax, std::abs(res[py * panel + px]));
    }
  const double decades = 4;
  for (std::size_t py = 0; py < panel; ++py)
    for (std::size_t px = 0; px < panel; ++px) {
      const double x = cx - half + 2 * half * (static_cast<double>(px) + 0.5) / panel;
      const double y = cy + half - 2 * half * (static_cast<double>(py) + 0.5) / panel;
      const bool inside = x * x + y * y < 1;
      for (int k = 0; k < 2; ++k) {
        const double v = (k == 0 ? ndf : m).eval_disk(x, y);
        std::uint8_t c[3] = {40, 40, 40};
        if (inside && v > 0 && vmax > 0)
          false_colour(std::clamp(1 + std::log10(v / vmax) / decades, 0.0, 1.0), c);
        else if (inside)
          false_colour(0, c);
        img.set(gap + static_cast<std::size_t>(k) * (panel + gap) + px, gap + py, c[0], c[1], c[2]);
      }
      std::uint8_t c[3] = {200, 200, 200};
      if (inside) diverging(rmax > 0 ? res[py * panel + px] / rmax : 0.0, c);
      img.set(gap + 2 * (panel + gap) + px, gap + py, c[0], c[1], c[2]);
    }
  // Label under the residual panel: the symmetric range as a fraction of the table maximum.
  char lab[64];
  std::snprintf(lab, sizeof lab, "+-%.2e", vmax > 0 ? rmax / vmax : 0.0);
  detail::draw_text(img, gap + 2 * (panel + gap), panel + gap + 6, lab, 3);
  std::snprintf(lab, sizeof lab, "%.0e", vmax);
  detail::draw_text(img, gap, panel + gap + 6, lab, 3);
  write_png(dir + "/compare.png", img);

  // slices.png: cuts along the fitted axes.
  // (The ellipsoid turns its axes by -theta_z; Beckmann/GGX by phi; a mixture by its first lobe's.)
  const NdfModel& model = ndf_model(r.model);
  double phi0 = 0, amax = 0;
  for (std::size_t i = 0; i < r.params.size(); ++i) {
    const NdfParam& q = model.params()[i];
    if (q.kind == NdfParam::Kind::Alpha) amax = std::max(amax, r.params.values[i]);
  }
  for (std::size_t i = r.params.size(); i-- > 0;) {
    const std::string& n = r.params.names[i];
    if (n.size() >= 7 && n.compare(n.size() - 7, 7, "theta_z") == 0) phi0 = -r.params.values[i];
    if (n.size() >= 3 && n.compare(n.size() - 3, 3, "phi") == 0) phi0 = r.params.values[i];
  }
  Plot p;
  p.title = r.model + " fit: cuts along the fitted axes";
  p.x.label = "signed polar angle of m (deg)";
  p.y.label = "D (1/sr)";
  p.y.scale = AxisScale::Log;
  const double lim = std::min(90.0, std::atan(6 * amax + 0.1) * 180 / kPi);
  p.x.min = -lim;
  p.x.max = lim;
  p.y.min = vmax * 1e-5;
  for (int k = 0; k < 2; ++k) {
    const double ph = phi0 + k * kPi / 2;
    const NdfSlice st = ndf.slice(ph, 2049), sm = m.slice(ph, 2049);
    std::vector<double> deg(st.theta.size());
    for (std::size_t i = 0; i < deg.size(); ++i) deg[i] = st.theta[i] * 180 / kPi;
    const std::string axis = k == 0 ? "alpha_x axis" : "alpha_y axis";
    PlotSeries a(deg, st.value, "measured, " + axis, PlotStyle::Line);
    a.color = plot_palette(static_cast<std::size_t>(2 * k));
    PlotSeries b(deg, sm.value, "fit, " + axis, PlotStyle::Dashed);
    b.color = plot_palette(static_cast<std::size_t>(2 * k + 1));
    p.add(a);
    p.add(b);
  }
  p.write_png(dir + "/slices.png", 800, 520);

  NdfPreviewOptions po;
  po.zoom = true;
  po.size = 384;
  write_ndf_preview(ndf, dir + "/measured.png", po);
  write_ndf_preview(m, dir + "/fit.png", po);
}

}  // namespace microbrdf
