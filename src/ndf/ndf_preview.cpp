// Log-scale false-colour previews of tabulated NDFs: the disk (m_x to the right, m_y up), the
// unit circle, an optional zoom panel around the peak and a colour bar labelled in decades
// of 1/sr.
#include "microbrdf/ndf_preview.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "core/bitmap_font.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/image.hpp"

namespace microbrdf {
namespace {

constexpr std::uint8_t kBackground[3] = {36, 36, 40};   // outside the disk, margins
constexpr std::uint8_t kBelow[3] = {6, 6, 10};          // zero / below the colour range
constexpr std::uint8_t kLine[3] = {210, 210, 210};      // circle, frames, zoom rectangle
constexpr std::uint8_t kUnmeasured[3] = {96, 96, 104};  // NaN nodes (no measurement)
constexpr std::uint8_t kText[3] = {230, 230, 230};
constexpr std::size_t kMargin = 10, kBar = 16;
constexpr int kFont = 2;

struct LogScale {
  double top = 0;      // log10 of the maximum
  double decades = 4;  // span
  // 0..1 on the colour scale, or < 0 when below the range / zero.
  double operator()(double v) const {
    if (!(v > 0)) return -1;
    return (std::log10(v) - (top - decades)) / decades;
  }
};

void paint(RgbImage& img, std::size_t x, std::size_t y, const std::uint8_t c[3]) {
  if (x < img.width && y < img.height) img.set(x, y, c[0], c[1], c[2]);
}

void colour_of(double t, std::uint8_t rgb[3]) {
  if (t < 0) {
    std::copy(kBelow, kBelow + 3, rgb);
    return;
  }
  false_colour(std::min(t, 1.0), rgb);
}

// Renders the square window [cx-hw, cx+hw] x [cy-hw, cy+hw] of the disk into img at (x0, y0),
// `size` pixels square; m_y grows upwards. Each pixel averages ss x ss bilinear samples.
void render_panel(const TabulatedNdf& ndf, const LogScale& scale, RgbImage& img, std::size_t x0,
                  std::size_t y0, std::size_t size, double cx, double cy, double hw, int ss) {
  const double px_w = 2 * hw / static_cast<double>(size);
  std::uint8_t rgb[3];
  for (std::size_t py = 0; py < size; ++py)
    for (std::size_t px = 0; px < size; ++px) {
      double sum = 0;
      int inside = 0;
      for (int sy = 0; sy < ss; ++sy)
        for (int sx = 0; sx < ss; ++sx) {
          const double mx = cx - hw + (static_cast<double>(px) + (sx + 0.5) / ss) * px_w;
          const double my = cy + hw - (static_cast<double>(py) + (sy + 0.5) / ss) * px_w;
          if (mx * mx + my * my > 1) continue;
          sum += ndf.eval_disk(mx, my);
          ++inside;
        }
      if (inside == 0) {
        paint(img, x0 + px, y0 + py, kBackground);
        continue;
      }
      if (std::isnan(sum)) {
        paint(img, x0 + px, y0 + py, kUnmeasured);
        continue;
      }
      colour_of(scale(sum / (ss * ss)), rgb);
      paint(img, x0 + px, y0 + py, rgb);
    }
}

// The unit circle of a panel showing [cx-hw, cx+hw]^2, clipped to the panel.
void draw_circle(RgbImage& img, std::size_t x0, std::size_t y0, std::size_t size, double cx,
                 double cy, double hw) {
  const double scale = static_cast<double>(size) / (2 * hw);
  const int steps = static_cast<int>(8 * size);
  for (int k = 0; k < steps; ++k) {
    const double a = 2 * std::numbers::pi * k / steps;
    const double px = (std::cos(a) - (cx - hw)) * scale, py = ((cy + hw) - std::sin(a)) * scale;
    if (px < 0 || py < 0 || px >= static_cast<double>(size) || py >= static_cast<double>(size))
      continue;
    paint(img, x0 + static_cast<std::size_t>(px), y0 + static_cast<std::size_t>(py), kLine);
  }
}

void draw_rect(RgbImage& img, std::size_t x0, std::size_t y0, std::size_t x1, std::size_t y1) {
  for (std::size_t x = x0; x <= x1; ++x) {
    paint(img, x, y0, kLine);
    paint(img, x, y1, kLine);
  }
  for (std::size_t y = y0; y <= y1; ++y) {
    paint(img, x0, y, kLine);
    paint(img, x1, y, kLine);
  }
}

}  // namespace

RgbImage render_ndf_preview(const TabulatedNdf& ndf, const NdfPreviewOptions& opt) {
  const std::size_t size = std::clamp<std::size_t>(opt.size, 16, 8192);
  const double decades = opt.decades > 0 ? opt.decades : 4;
  double vmax = 0;
  for (std::size_t iy = 0; iy < ndf.resolution(); ++iy)
    for (std::size_t ix = 0; ix < ndf.resolution(); ++ix) {
      const double x = ndf.node_x(ix), y = ndf.node_y(iy);
      if (x * x + y * y <= 1) vmax = std::max(vmax, ndf.at(ix, iy));
    }
  LogScale scale{vmax > 0 ? std::log10(vmax) : 0.0, decades};

  const bool title = !opt.title.empty() && detail::font_can_draw(opt.title);
  const std::size_t top = kMargin + (title ? detail::text_height(kFont) + kMargin : 0);
  const std::size_t panels = opt.zoom ? 2 : 1;
  const std::size_t bar_x = kMargin + panels * (size + kMargin);
  // Decade labels "1e<k>", k from the bottom to the top of the range.
  const int k_hi = static_cast<int>(std::floor(scale.top + 1e-9));
  const int k_lo = static_cast<int>(std::ceil(scale.top - decades - 1e-9));
  std::size_t label_w = detail::text_width("1/sr", kFont);
  for (int k = k_lo; k <= k_hi; ++k)
    label_w = std::max(label_w, detail::text_width("1e" + std::to_string(k), kFont));
  const std::size_t width = bar_x + kBar + 6 + label_w + kMargin;
  const std::size_t height = top + size + kMargin + detail::text_height(kFont) + kMargin;
  RgbImage img(width, height);
  for (std::size_t y = 0; y < height; ++y)
    for (std::size_t x = 0; x < width; ++x) paint(img, x, y, kBackground);
  if (title)
    detail::draw_text(img, kMargin, kMargin, opt.title, kFont, kText[0], kText[1], kText[2]);

  // Full view: supersample so that every node contributes when nodes outnumber pixels.
  const int ss = static_cast<int>(std::clamp<double>(
      std::ceil(static_cast<double>(ndf.resolution()) / static_cast<double>(size)), 1, 4));
  render_panel(ndf, scale, img, kMargin, top, size, 0, 0, 1, ss);
  draw_circle(img, kMargin, top, size, 0, 0, 1);

  if (opt.zoom) {
    const Eigen::Vector3d pk = ndf.peak();
    double hw = opt.zoom_half_width;
    if (!(hw > 0)) {
      double s = std::max(ndf.rms_slope(0), ndf.rms_slope(std::numbers::pi / 2));
      if (!std::isfinite(s)) {  // unmeasured (NaN) nodes: moments of the measured part
        TabulatedNdf filled = ndf;
        for (double& v : filled.values())
          if (std::isnan(v)) v = 0;
        s = std::max(filled.rms_slope(0), filled.rms_slope(std::numbers::pi / 2));
      }
      hw = std::max(4 * s / std::sqrt(1 + s * s), 8 * ndf.spacing());
    }
    hw = std::min(hw, 1.0);
    const std::size_t zx = kMargin + size + kMargin;
    render_panel(ndf, scale, img, zx, top, size, pk.x(), pk.y(), hw, 1);
    draw_circle(img, zx, top, size, pk.x(), pk.y(), hw);
    draw_rect(img, zx - 1, top - 1, zx + size, top + size);
    // The zoom region on the full view.
    const double f = static_cast<double>(size) / 2;
    auto to_px = [&](double v) {
      return static_cast<std::size_t>(
          std::clamp(std::floor(v), 0.0, static_cast<double>(size - 1)));
    };
    draw_rect(img, kMargin + to_px((pk.x() - hw + 1) * f), top + to_px((1 - (pk.y() + hw)) * f),
              kMargin + to_px((pk.x() + hw + 1) * f), top + to_px((1 - (pk.y() - hw)) * f));
  }

  // Colour bar: top = maximum, bottom = maximum / 10^decades.
  std::uint8_t rgb[3];
  for (std::size_t y = 0; y < size; ++y) {
    false_colour(1.0 - static_cast<double>(y) / static_cast<double>(size - 1), rgb);
    for (std::size_t x = bar_x; x < bar_x + kBar; ++x) paint(img, x, top + y, rgb);
  }
  for (int k = k_lo; k <= k_hi; ++k) {
    const double t = (scale.top - k) / decades;  // 0 at the top
    const auto y = top + static_cast<std::size_t>(std::lround(t * static_cast<double>(size - 1)));
    for (std::size_t x = bar_x + kBar; x < bar_x + kBar + 4; ++x) paint(img, x, y, kLine);
    const std::size_t ty = y >= 5 ? std::min(y - 5, top + size - 10) : 0;
    detail::draw_text(img, bar_x + kBar + 6, ty, "1e" + std::to_string(k), kFont, kText[0],
                      kText[1], kText[2]);
  }
  detail::draw_text(img, bar_x, top + size + kMargin, "1/sr", kFont, kText[0], kText[1], kText[2]);
  return img;
}

void write_ndf_preview(const TabulatedNdf& ndf, const std::string& png_path,
                       const NdfPreviewOptions& opt) {
  write_png(png_path, render_ndf_preview(ndf, opt));
}

}  // namespace microbrdf
