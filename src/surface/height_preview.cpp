// False-colour height-map previews with a colour bar (include/microbrdf/height_preview.hpp).
#include "microbrdf/height_preview.hpp"

#include <algorithm>
#include <cmath>

#include "core/bitmap_font.hpp"
#include "microbrdf/units.hpp"

namespace microbrdf {

RgbImage render_height_preview(const Surface& s, std::size_t max_size) {
  // Box-filter down to at most max_size on the long side, keeping the physical aspect ratio.
  const double w_m = s.width(), h_m = s.height();
  // Square output pixels (metres each): the finer spacing, or coarser to fit max_size.
  const double px_m =
      std::max(std::min(s.dx, s.dy), std::max(w_m, h_m) / static_cast<double>(max_size));
  const std::size_t w = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(w_m / px_m)));
  const std::size_t h = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(h_m / px_m)));
  std::vector<double> img(w * h, 0.0), cnt(w * h, 0.0);
  for (std::size_t iy = 0; iy < s.ny; ++iy)
    for (std::size_t ix = 0; ix < s.nx; ++ix) {
      std::size_t i = iy * s.nx + ix;
      if (!s.valid[i]) continue;
      auto ox =
          std::min(w - 1, static_cast<std::size_t>((static_cast<double>(ix) + 0.5) * s.dx / px_m));
      auto oy =
          std::min(h - 1, static_cast<std::size_t>((static_cast<double>(iy) + 0.5) * s.dy / px_m));
      img[oy * w + ox] += s.z[i];
      cnt[oy * w + ox] += 1;
    }
  std::vector<double> vals;
  for (std::size_t i = 0; i < img.size(); ++i)
    if (cnt[i] > 0) {
      img[i] /= cnt[i];
      vals.push_back(img[i]);
    }
  double lo = 0, hi = 1;
  if (!vals.empty()) {
    std::sort(vals.begin(), vals.end());
    lo = vals[static_cast<std::size_t>(0.005 * static_cast<double>(vals.size() - 1))];
    hi = vals[static_cast<std::size_t>(0.995 * static_cast<double>(vals.size() - 1))];
    if (hi <= lo) hi = lo + 1e-12;
  }
  auto label = [&](double v) { return format_length(v, 3); };
  const std::size_t bar = 14, margin = 8,
                    label_w = std::max(detail::text_width(label(hi), 2),
                                       detail::text_width(label(lo), 2)) +
                              4;
  RgbImage out(w + margin + bar + margin + label_w, std::max<std::size_t>(h, 60));
  std::fill(out.pixels.begin(), out.pixels.end(), 255);
  std::uint8_t rgb[3];
  for (std::size_t y = 0; y < h; ++y)
    for (std::size_t x = 0; x < w; ++x) {
      std::size_t i = y * w + x;
      if (cnt[i] == 0) {
        out.set(x, y, 128, 128, 128);
        continue;
      }
      false_colour((img[i] - lo) / (hi - lo), rgb);
      // Hill-shading from the upper left, from neighbouring preview pixels.
      double shade = 1.0;
      if (x + 1 < w && y + 1 < h && cnt[i + 1] > 0 && cnt[i + w] > 0) {
        double gx = (img[i + 1] - img[i]) / (hi - lo), gy = (img[i + w] - img[i]) / (hi - lo);
        shade = std::clamp(1.0 - 2.0 * (gx + gy), 0.75, 1.15);
      }
      out.set(x, y, static_cast<std::uint8_t>(std::min(255.0, rgb[0] * shade)),
              static_cast<std::uint8_t>(std::min(255.0, rgb[1] * shade)),
              static_cast<std::uint8_t>(std::min(255.0, rgb[2] * shade)));
    }
  const std::size_t bx = w + margin, bh = out.height;
  for (std::size_t y = 0; y < bh; ++y) {
    false_colour(1.0 - static_cast<double>(y) / static_cast<double>(bh - 1), rgb);
    for (std::size_t x = bx; x < bx + bar; ++x) out.set(x, y, rgb[0], rgb[1], rgb[2]);
  }
  detail::draw_text(out, bx + bar + 4, 2, label(hi), 2);
  detail::draw_text(out, bx + bar + 4, bh - 14, label(lo), 2);
  return out;
}

}  // namespace microbrdf
