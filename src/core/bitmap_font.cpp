// Labels on raster previews drawn with Cairo (see bitmap_font.hpp).
#include "core/bitmap_font.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

#include "core/cairo_runtime.hpp"

namespace microbrdf::detail {
namespace {

// DejaVu Sans: digits and capitals are 0.729 em tall.
constexpr double kCapPerEm = 0.729;
double font_px(int scale) { return 5.0 * std::max(scale, 1) / kCapPerEm; }

void set_font(cairo_t* cr, int scale) {
  cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, font_px(scale));
  // Grey anti-aliasing, no hinting: the same pixels whatever the display settings.
  cairo_font_options_t* fo = cairo_font_options_create();
  cairo_font_options_set_antialias(fo, CAIRO_ANTIALIAS_GRAY);
  cairo_font_options_set_hint_style(fo, CAIRO_HINT_STYLE_NONE);
  cairo_font_options_set_hint_metrics(fo, CAIRO_HINT_METRICS_OFF);
  cairo_set_font_options(cr, fo);
  cairo_font_options_destroy(fo);
}

struct Surface {
  cairo_surface_t* s;
  cairo_t* cr;
  Surface(int w, int h)
      : s(cairo_image_surface_create(CAIRO_FORMAT_ARGB32, w, h)), cr(cairo_create(s)) {}
  ~Surface() {
    cairo_destroy(cr);
    cairo_surface_destroy(s);
  }
  Surface(const Surface&) = delete;
  Surface& operator=(const Surface&) = delete;
};

double advance(const std::string& text, int scale) {
  load_cairo();
  Surface m(1, 1);
  set_font(m.cr, scale);
  cairo_text_extents_t e;
  cairo_text_extents(m.cr, text.c_str(), &e);
  return e.x_advance;
}

}  // namespace

bool font_can_draw(const std::string&) { return true; }

std::size_t text_width(const std::string& text, int scale) {
  if (text.empty()) return 0;
  return static_cast<std::size_t>(std::ceil(advance(text, scale)));
}

void draw_text(RgbImage& img, std::size_t x0, std::size_t y0, const std::string& text, int scale,
               std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  load_cairo();
  if (text.empty() || x0 >= img.width || y0 >= img.height) return;
  const double px = font_px(scale);
  // The glyphs' box: from an ascent above the caps (accents) to the descenders.
  const int pad = static_cast<int>(std::ceil(0.3 * px));
  const int w = static_cast<int>(std::ceil(advance(text, scale))) + 2 * pad;
  const int h = static_cast<int>(std::ceil(1.6 * px)) + 2 * pad;
  Surface t(w, h);
  set_font(t.cr, scale);
  cairo_set_source_rgba(t.cr, 0, 0, 0, 1);
  const double baseline = pad + 5.0 * std::max(scale, 1);  // caps' top at y = pad
  cairo_move_to(t.cr, pad, baseline);
  cairo_show_text(t.cr, text.c_str());
  cairo_surface_flush(t.s);
  const unsigned char* data = cairo_image_surface_get_data(t.s);
  const int stride = cairo_image_surface_get_stride(t.s);
  const std::uint8_t col[3] = {r, g, b};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      // ARGB32 in native byte order: the alpha is the top byte of each 32-bit pixel.
      std::uint32_t v;
      std::copy_n(data + y * stride + 4 * x, 4, reinterpret_cast<unsigned char*>(&v));
      const double a = static_cast<double>(v >> 24) / 255.0;
      if (a <= 0) continue;
      const long ix = static_cast<long>(x0) + x - pad, iy = static_cast<long>(y0) + y - pad;
      if (ix < 0 || iy < 0 || ix >= static_cast<long>(img.width) ||
          iy >= static_cast<long>(img.height))
        continue;
      std::uint8_t* p =
          &img.pixels[(static_cast<std::size_t>(iy) * img.width + static_cast<std::size_t>(ix)) *
                      3];
      for (int c = 0; c < 3; ++c)
        p[c] = static_cast<std::uint8_t>(std::lround(a * col[c] + (1 - a) * p[c]));
    }
}

}  // namespace microbrdf::detail
