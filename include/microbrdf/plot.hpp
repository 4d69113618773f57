#pragma once
// Small 2-D plots for the docs, validation figures and the HTML report: line / marker / dashed
// series, linear or log axes, legend, optional error bars and bands. One drawing routine
// renders to PNG (raster) and SVG (vector, for embedding in HTML). Cairo does the drawing.
//
//   Plot p;
//   p.title = "Free travel probability, s = 1";
//   p.x.label = "theta (deg)";
//   p.y.label = "Gamma_0";
//   p.add({xs, ys, "analytic"});
//   p.add({xs, sim, "simulated", PlotStyle::Markers});
//   p.write("ftp.png");   // or .svg
//
// Data that cannot be drawn are dropped, never moved: non-finite values on any axis, and
// values <= 0 on a log axis. A line is broken where a point was dropped. Error bars whose
// lower end is <= 0 on a log y axis are drawn down to the bottom of the frame. A plot with
// nothing drawable throws InputError; a file that cannot be written throws FileError.
// Files are written atomically (AtomicFile): a failed write leaves no partial output.

#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace microbrdf {

enum class PlotStyle {
  Line,         ///< solid line through the points
  Dashed,       ///< dashed line
  Dotted,       ///< dotted line
  Markers,      ///< markers only
  LineMarkers,  ///< solid line and markers
};

enum class MarkerShape { Circle, Square, Triangle, Diamond };

/// sRGB colour, components in [0, 1].
struct PlotColor {
  double r = 0, g = 0, b = 0;
};

/// Default palette (10 colours, the widely used "tab10" set); cycles with the series index.
PlotColor plot_palette(std::size_t index);

struct PlotSeries {
  PlotSeries() = default;
  PlotSeries(std::vector<double> x_, std::vector<double> y_, std::string label_ = {},
             PlotStyle style_ = PlotStyle::Line)
      : x(std::move(x_)), y(std::move(y_)), label(std::move(label_)), style(style_) {}

  std::vector<double> x, y;
  std::string label;  ///< shown in the legend; empty = not in the legend
  PlotStyle style = PlotStyle::Line;
  std::optional<PlotColor> color;  ///< default: plot_palette(series index)
  MarkerShape marker = MarkerShape::Circle;
  double line_width = 1.6;   ///< px (PNG) / pt (SVG)
  double marker_size = 3.0;  ///< marker radius
  /// Optional symmetric error bars: y +- y_err (same length as y, or empty).
  std::vector<double> y_err;
  /// Optional shaded band between band_lo and band_hi (same length as x, or empty).
  std::vector<double> band_lo, band_hi;
};

enum class AxisScale { Linear, Log };

struct PlotAxis {
  std::string label;  ///< with its unit, e.g. "theta (deg)"
  AxisScale scale = AxisScale::Linear;
  std::optional<double> min, max;  ///< fixed limits; default: from the data (padded)
};

enum class LegendPlace { Auto, TopRight, TopLeft, BottomRight, BottomLeft, None };

class Plot {
 public:
  std::string title;
  PlotAxis x, y;
  std::vector<PlotSeries> series;
  LegendPlace legend = LegendPlace::Auto;  ///< Auto: the corner covering the fewest points
  double font_size = 13;                   ///< base font size, px / pt

  PlotSeries& add(PlotSeries s) {
    series.push_back(std::move(s));
    return series.back();
  }

  /// PNG of width x height pixels (whatever the extension of path). Throws InputError (nothing to
  /// draw, bad limits) or FileError (cannot write).
  void write_png(const std::string& path, int width = 800, int height = 560) const;
  /// SVG of width x height points. The SVG carries <title> and <desc> elements holding the
  /// plot title and axis labels as text (Cairo draws text as glyph outlines), so it is
  /// searchable and accessible when embedded in HTML.
  void write_svg(const std::string& path, int width = 800, int height = 560) const;
  /// By extension: .png or .svg (case-insensitive); anything else throws InputError.
  void write(const std::string& path, int width = 800, int height = 560) const;
};

/// Several plots in one image, row by row, `columns` per row, each cell cell_width x
/// cell_height. PNG or SVG by extension. Throws like Plot::write.
void write_plot_grid(const std::vector<Plot>& plots, std::size_t columns, const std::string& path,
                     int cell_width = 480, int cell_height = 360);

}  // namespace microbrdf
