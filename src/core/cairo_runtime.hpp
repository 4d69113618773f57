#pragma once
// Cairo, loaded when a plot or a text label is first drawn instead of at process start
// (core/runtime_library.hpp says why and how; Cairo brings X11, xcb, fontconfig, freetype and
// pixman).
#include <cairo-svg.h>
#include <cairo.h>

#include "core/runtime_library.hpp"

/// Every Cairo function the plots (plot/plot.cpp), the raster labels (core/bitmap_font.cpp) and
/// the report's version list call.
// clang-format off
#define MICROBRDF_CAIRO_FUNCTIONS(X) \
  X(cairo_arc) X(cairo_clip) X(cairo_close_path) X(cairo_create) X(cairo_destroy) \
  X(cairo_fill) X(cairo_fill_preserve) X(cairo_font_extents) \
  X(cairo_font_options_create) X(cairo_font_options_destroy) \
  X(cairo_font_options_set_antialias) X(cairo_font_options_set_hint_metrics) \
  X(cairo_font_options_set_hint_style) X(cairo_image_surface_create) \
  X(cairo_image_surface_get_data) X(cairo_image_surface_get_stride) X(cairo_line_to) \
  X(cairo_move_to) X(cairo_rotate) \
  X(cairo_new_sub_path) X(cairo_paint) X(cairo_rectangle) X(cairo_restore) \
  X(cairo_save) X(cairo_select_font_face) X(cairo_set_dash) \
  X(cairo_set_font_options) X(cairo_set_font_size) X(cairo_set_line_cap) \
  X(cairo_set_line_join) X(cairo_set_line_width) X(cairo_set_source_rgb) \
  X(cairo_set_source_rgba) X(cairo_show_text) X(cairo_status) \
  X(cairo_status_to_string) X(cairo_stroke) X(cairo_surface_destroy) \
  X(cairo_surface_finish) X(cairo_surface_flush) X(cairo_surface_status) \
  X(cairo_surface_write_to_png) X(cairo_svg_surface_create) X(cairo_text_extents) \
  X(cairo_translate) X(cairo_version_string)
// clang-format on

namespace microbrdf {
MICROBRDF_CAIRO_FUNCTIONS(MICROBRDF_RUNTIME_DECLARE)
}  // namespace microbrdf

namespace microbrdf::detail {

/// Loads Cairo (once per process; thread-safe). Throws std::runtime_error naming the library
/// and the Debian package when it cannot be loaded or lacks a symbol.
void load_cairo();

}  // namespace microbrdf::detail
