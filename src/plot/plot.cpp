// Plots with Cairo: one drawing routine, rendered to an image surface (PNG) or an SVG surface.
#include "microbrdf/plot.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <sstream>

#include "core/cairo_runtime.hpp"
#include "core/markup_escape.hpp"
#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/file_size_limit.hpp"
#include "plot/ticks.hpp"

namespace microbrdf {

PlotColor plot_palette(std::size_t index) {
  // "tab10": blue, orange, green, red, purple, brown, pink, grey, olive, cyan.
  static constexpr std::array<unsigned, 10> hex = {0x1f77b4, 0xff7f0e, 0x2ca02c, 0xd62728,
                                                   0x9467bd, 0x8c564b, 0xe377c2, 0x7f7f7f,
                                                   0xbcbd22, 0x17becf};
  unsigned h = hex[index % hex.size()];
  return {((h >> 16) & 0xff) / 255.0, ((h >> 8) & 0xff) / 255.0, (h & 0xff) / 255.0};
}

namespace {

using detail::Tick;

bool drawable(double v, AxisScale s) {
  return std::isfinite(v) && (s == AxisScale::Linear || v > 0);
}

std::string plot_name(const Plot& p) {
  return p.title.empty() ? std::string("plot") : "plot \"" + p.title + "\"";
}

struct Limits {
  double lo = 0, hi = 1;
};

// Data range along one axis over the points drawn (both coordinates drawable), with error
// bars and bands where they are drawable.
std::optional<Limits> data_range(const Plot& p, bool along_x) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  auto take = [&](double v, AxisScale sc) {
    if (drawable(v, sc)) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  };
  for (const auto& s : p.series) {
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      const bool pt = drawable(s.x[i], p.x.scale) && drawable(s.y[i], p.y.scale);
      if (along_x) {
        if (pt) take(s.x[i], p.x.scale);
        if (!s.band_lo.empty() && drawable(s.x[i], p.x.scale) &&
            (drawable(s.band_lo[i], p.y.scale) || drawable(s.band_hi[i], p.y.scale)))
          take(s.x[i], p.x.scale);
      } else {
        if (pt) {
          take(s.y[i], p.y.scale);
          if (!s.y_err.empty() && std::isfinite(s.y_err[i])) {
            take(s.y[i] + std::abs(s.y_err[i]), p.y.scale);
            take(s.y[i] - std::abs(s.y_err[i]), p.y.scale);
          }
        }
        if (!s.band_lo.empty() && drawable(s.x[i], p.x.scale)) {
          take(s.band_lo[i], p.y.scale);
          take(s.band_hi[i], p.y.scale);
        }
      }
    }
  }
  if (!(hi >= lo)) return std::nullopt;
  return Limits{lo, hi};
}

Limits axis_limits(const Plot& p, const PlotAxis& a, const Limits& data, const char* name) {
  const bool log = a.scale == AxisScale::Log;
  Limits l = data;
  if (log) {
    l.lo = std::log10(l.lo);
    l.hi = std::log10(l.hi);
  }
  if (l.hi == l.lo) {
    double d = log ? 0.3 : (l.lo == 0 ? 1.0 : 0.1 * std::abs(l.lo));
    l.lo -= d;
    l.hi += d;
  } else {
    double pad = 0.04 * (l.hi - l.lo);
    l.lo -= pad;
    l.hi += pad;
  }
  if (log) {
    l.lo = std::pow(10.0, l.lo);
    l.hi = std::pow(10.0, l.hi);
  }
  if (a.min) l.lo = *a.min;
  if (a.max) l.hi = *a.max;
  if (!std::isfinite(l.lo) || !std::isfinite(l.hi) || !(l.hi > l.lo))
    throw InputError(plot_name(p) + ": " + name + " axis limits must be finite with min < max");
  if (log && !(l.lo > 0))
    throw InputError(plot_name(p) + ": " + name + " axis is logarithmic, its limits must be > 0");
  return l;
}

struct Prepared {
  Limits x, y;
};

Prepared prepare(const Plot& p) {
  for (const auto& s : p.series) {
    const std::string who = plot_name(p) + ", series \"" + s.label + "\"";
    if (s.x.size() != s.y.size()) throw InputError(who + ": x and y differ in length");
    if (!s.y_err.empty() && s.y_err.size() != s.y.size())
      throw InputError(who + ": y_err must be empty or as long as y");
    if (s.band_lo.size() != s.band_hi.size() ||
        (!s.band_lo.empty() && s.band_lo.size() != s.x.size()))
      throw InputError(who + ": band_lo and band_hi must be empty or as long as x");
  }
  auto rx = data_range(p, true), ry = data_range(p, false);
  if (!rx || !ry) {
    std::string why =
        p.series.empty() ? "it has no series" : "no series has a drawable point (finite";
    if (!p.series.empty()) {
      if (p.x.scale == AxisScale::Log || p.y.scale == AxisScale::Log)
        why += ", and > 0 on a log axis";
      why += ")";
    }
    throw InputError(plot_name(p) + ": nothing to draw: " + why);
  }
  return {axis_limits(p, p.x, *rx, "x"), axis_limits(p, p.y, *ry, "y")};
}

// Data -> device coordinate along one axis.
struct Map {
  double lo, hi, p0, p1;
  bool log;
  double operator()(double v) const {
    double t = log ? (std::log10(v) - std::log10(lo)) / (std::log10(hi) - std::log10(lo))
                   : (v - lo) / (hi - lo);
    return p0 + t * (p1 - p0);
  }
};

struct CairoDel {
  void operator()(cairo_t* c) const { cairo_destroy(c); }
  void operator()(cairo_surface_t* s) const { cairo_surface_destroy(s); }
};
using CairoPtr = std::unique_ptr<cairo_t, CairoDel>;
using SurfacePtr = std::unique_ptr<cairo_surface_t, CairoDel>;

void set_color(cairo_t* cr, const PlotColor& c, double alpha = 1) {
  cairo_set_source_rgba(cr, c.r, c.g, c.b, alpha);
}

double text_width(cairo_t* cr, const std::string& s) {
  cairo_text_extents_t e;
  cairo_text_extents(cr, s.c_str(), &e);
  return e.x_advance;
}

// Text anchored at (x, y): ax = 0 left, 0.5 centre, 1 right; ay likewise for top/middle/bottom
// of the font's ascent.
void draw_text(cairo_t* cr, const std::string& s, double x, double y, double ax, double ay) {
  cairo_text_extents_t e;
  cairo_text_extents(cr, s.c_str(), &e);
  cairo_font_extents_t fe;
  cairo_font_extents(cr, &fe);
  const double h = fe.ascent * 0.8;  // cap height, roughly
  cairo_move_to(cr, x - ax * e.x_advance, y + h - ay * h);
  cairo_show_text(cr, s.c_str());
}

void marker_path(cairo_t* cr, MarkerShape m, double x, double y, double r) {
  switch (m) {
    case MarkerShape::Circle:
      cairo_new_sub_path(cr);
      cairo_arc(cr, x, y, r, 0, 2 * M_PI);
      break;
    case MarkerShape::Square:
      cairo_rectangle(cr, x - 0.9 * r, y - 0.9 * r, 1.8 * r, 1.8 * r);
      break;
    case MarkerShape::Triangle:
      cairo_move_to(cr, x, y - 1.2 * r);
      cairo_line_to(cr, x + 1.1 * r, y + 0.8 * r);
      cairo_line_to(cr, x - 1.1 * r, y + 0.8 * r);
      cairo_close_path(cr);
      break;
    case MarkerShape::Diamond:
      cairo_move_to(cr, x, y - 1.3 * r);
      cairo_line_to(cr, x + 1.1 * r, y);
      cairo_line_to(cr, x, y + 1.3 * r);
      cairo_line_to(cr, x - 1.1 * r, y);
      cairo_close_path(cr);
      break;
  }
}

bool has_line(PlotStyle s) { return s != PlotStyle::Markers; }
bool has_markers(PlotStyle s) { return s == PlotStyle::Markers || s == PlotStyle::LineMarkers; }

void set_line_style(cairo_t* cr, const PlotSeries& s) {
  cairo_set_line_width(cr, s.line_width);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  if (s.style == PlotStyle::Dashed) {
    const double d[] = {4.0 * s.line_width, 2.5 * s.line_width};
    cairo_set_dash(cr, d, 2, 0);
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
  } else if (s.style == PlotStyle::Dotted) {
    const double d[] = {0.1, 2.2 * s.line_width};
    cairo_set_dash(cr, d, 2, 0);
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  } else {
    cairo_set_dash(cr, nullptr, 0, 0);
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  }
}

std::vector<Tick> ticks_for(const Limits& l, AxisScale sc, int target) {
  return sc == AxisScale::Log ? detail::log_ticks(l.lo, l.hi)
                              : detail::linear_ticks(l.lo, l.hi, target);
}

// Draws plot p into the rectangle [0, W] x [0, H] of cr.
void draw_plot(cairo_t* cr, const Plot& p, const Prepared& pr, double W, double H) {
  const double fs = p.font_size;
  cairo_save(cr);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_rectangle(cr, 0, 0, W, H);
  cairo_fill(cr);
  cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, fs * 0.9);

  const int xtarget = std::max(3, static_cast<int>(W / (7 * fs)));
  const int ytarget = std::max(3, static_cast<int>(H / (4 * fs)));
  auto xt = ticks_for(pr.x, p.x.scale, xtarget);
  auto yt = ticks_for(pr.y, p.y.scale, ytarget);
  double ylab_w = 0, last_x_w = 0;
  for (auto& t : yt) ylab_w = std::max(ylab_w, text_width(cr, t.label));
  for (auto& t : xt)
    if (!t.label.empty()) last_x_w = text_width(cr, t.label);

  const double tick = 0.4 * fs, gap = 0.4 * fs;
  const double top = p.title.empty() ? fs : 2.4 * fs;
  const double left = 0.6 * fs + (p.y.label.empty() ? 0 : 1.6 * fs) + ylab_w + gap + tick;
  const double bottom = 0.6 * fs + (p.x.label.empty() ? 0 : 1.6 * fs) + fs + gap + tick;
  const double right = std::max(1.2 * fs, 0.5 * last_x_w + 0.4 * fs);
  auto ok = [&](double x, double y) { return drawable(x, p.x.scale) && drawable(y, p.y.scale); };

  // The legend's box (font 0.9 fs, set above) and where it goes: a corner of the frame that no
  // curve, marker or band crosses, else outside the frame on the right (the frame narrows).
  std::vector<std::size_t> entries;
  for (std::size_t i = 0; i < p.series.size(); ++i)
    if (!p.series[i].label.empty()) entries.push_back(i);
  const bool legend = !entries.empty() && p.legend != LegendPlace::None;
  double tw = 0;
  for (auto i : entries) tw = std::max(tw, text_width(cr, p.series[i].label));
  const double lpad = 0.5 * fs, sample = 2.2 * fs, lrow = 1.35 * fs, lm = 0.5 * fs;
  const double bw = lpad + sample + lpad + tw + lpad,
               bh = lpad + lrow * static_cast<double>(entries.size()) + 0.3 * lpad;
  bool outside = false;
  double X0 = left, X1 = W - right, Y0 = H - bottom, Y1 = top;  // Y grows downwards
  auto corner = [&](LegendPlace pl) -> std::pair<double, double> {
    if (outside) return {X1 + lm, Y1};
    switch (pl) {
      case LegendPlace::TopLeft:
        return {X0 + lm, Y1 + lm};
      case LegendPlace::BottomRight:
        return {X1 - lm - bw, Y0 - lm - bh};
      case LegendPlace::BottomLeft:
        return {X0 + lm, Y0 - lm - bh};
      default:
        return {X1 - lm - bw, Y1 + lm};
    }
  };
  LegendPlace place = p.legend;
  if (legend && place == LegendPlace::Auto) {
    // Device points of everything drawn, lines sampled every 2 px between their vertices.
    const Map mx0{pr.x.lo, pr.x.hi, X0, X1, p.x.scale == AxisScale::Log};
    const Map my0{pr.y.lo, pr.y.hi, Y0, Y1, p.y.scale == AxisScale::Log};
    std::vector<std::pair<double, double>> pts;
    auto keep = [&](double x, double y) {
      if (x >= X0 && x <= X1 && y >= Y1 && y <= Y0) pts.emplace_back(x, y);
    };
    for (const auto& s : p.series) {
      bool have = false;
      double px = 0, py = 0;
      for (std::size_t i = 0; i < s.x.size(); ++i) {
        for (const std::vector<double>* v : {&s.y, &s.band_lo, &s.band_hi}) {
          if (v->size() != s.x.size() || !ok(s.x[i], (*v)[i])) continue;
          keep(mx0(s.x[i]), my0((*v)[i]));
        }
        if (!ok(s.x[i], s.y[i])) {
          have = false;
          continue;
        }
        const double x = mx0(s.x[i]), y = my0(s.y[i]);
        if (have && has_line(s.style)) {
          const int n = static_cast<int>(std::min(2000.0, std::hypot(x - px, y - py) / 2));
          for (int k = 1; k < n; ++k) {
            const double f = static_cast<double>(k) / n;
            keep(px + f * (x - px), py + f * (y - py));
          }
        }
        have = true;
        px = x;
        py = y;
      }
    }
    std::size_t best = std::numeric_limits<std::size_t>::max();
    for (auto c : {LegendPlace::TopRight, LegendPlace::TopLeft, LegendPlace::BottomRight,
                   LegendPlace::BottomLeft}) {
      auto [lx, ly] = corner(c);
      std::size_t n = 0;
      for (auto& [x, y] : pts)
        n += (x >= lx - 4 && x <= lx + bw + 4 && y >= ly - 4 && y <= ly + bh + 4);
      if (n < best) {
        best = n;
        place = c;
      }
    }
    // Every corner covers a curve: outside, if the frame keeps at least half the width.
    if (best > 0 && (X1 - X0) - (bw + lm) >= 0.5 * (X1 - X0)) {
      outside = true;
      X1 -= bw + lm;
    }
  }
  if (X1 - X0 < 20 || Y0 - Y1 < 20) {
    cairo_restore(cr);
    throw InputError(plot_name(p) + ": image too small for the axes and labels");
  }
  const Map mx{pr.x.lo, pr.x.hi, X0, X1, p.x.scale == AxisScale::Log};
  const Map my{pr.y.lo, pr.y.hi, Y0, Y1, p.y.scale == AxisScale::Log};
  auto in_x = [&](double v) { return v >= pr.x.lo && v <= pr.x.hi; };
  auto in_y = [&](double v) { return v >= pr.y.lo && v <= pr.y.hi; };

  // Grid (major ticks light, minor lighter), then the frame, ticks and labels.
  cairo_set_line_width(cr, 1);
  for (int pass = 0; pass < 2; ++pass) {
    const double g = pass == 0 ? 0.95 : 0.88;
    cairo_set_source_rgb(cr, g, g, g);
    for (auto& t : xt)
      if (in_x(t.value) && (pass == 0) == t.label.empty()) {
        double x = std::round(mx(t.value)) + 0.5;
        cairo_move_to(cr, x, Y0);
        cairo_line_to(cr, x, Y1);
      }
    for (auto& t : yt)
      if (in_y(t.value) && (pass == 0) == t.label.empty()) {
        double y = std::round(my(t.value)) + 0.5;
        cairo_move_to(cr, X0, y);
        cairo_line_to(cr, X1, y);
      }
    cairo_stroke(cr);
  }
  cairo_set_source_rgb(cr, 0.15, 0.15, 0.15);
  for (auto& t : xt) {
    if (!in_x(t.value)) continue;
    double x = std::round(mx(t.value)) + 0.5, len = t.label.empty() ? 0.5 * tick : tick;
    cairo_move_to(cr, x, Y0);
    cairo_line_to(cr, x, Y0 + len);
    if (!t.label.empty()) draw_text(cr, t.label, x, Y0 + tick + gap, 0.5, 0);
  }
  for (auto& t : yt) {
    if (!in_y(t.value)) continue;
    double y = std::round(my(t.value)) + 0.5, len = t.label.empty() ? 0.5 * tick : tick;
    cairo_move_to(cr, X0 - len, y);
    cairo_line_to(cr, X0, y);
    if (!t.label.empty()) draw_text(cr, t.label, X0 - tick - gap, y, 1, 0.5);
  }
  cairo_stroke(cr);
  cairo_rectangle(cr, std::round(X0) + 0.5, std::round(Y1) + 0.5, std::round(X1 - X0),
                  std::round(Y0 - Y1));
  cairo_stroke(cr);

  cairo_set_font_size(cr, fs);
  if (!p.x.label.empty()) draw_text(cr, p.x.label, 0.5 * (X0 + X1), H - 0.6 * fs, 0.5, 1);
  if (!p.y.label.empty()) {
    cairo_save(cr);
    // Rotated a quarter turn anticlockwise; the baseline sits 1.5 fs from the left edge, so
    // the glyphs (ascent about 0.9 fs) start 0.6 fs from it.
    cairo_translate(cr, 1.5 * fs, 0.5 * (Y0 + Y1));
    cairo_rotate(cr, -M_PI / 2);
    cairo_text_extents_t e;
    cairo_text_extents(cr, p.y.label.c_str(), &e);
    cairo_move_to(cr, -0.5 * e.x_advance, 0);
    cairo_show_text(cr, p.y.label.c_str());
    cairo_restore(cr);
  }
  if (!p.title.empty()) {
    cairo_save(cr);
    cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
    cairo_set_font_size(cr, 1.1 * fs);
    draw_text(cr, p.title, 0.5 * (X0 + X1), 0.9 * fs, 0.5, 0.5);
    cairo_restore(cr);
  }

  // Series, clipped to the frame: bands, lines, error bars, markers.
  cairo_save(cr);
  cairo_rectangle(cr, X0, Y1, X1 - X0, Y0 - Y1);
  cairo_clip(cr);
  for (std::size_t si = 0; si < p.series.size(); ++si) {
    const auto& s = p.series[si];
    const PlotColor c = s.color.value_or(plot_palette(si));
    if (!s.band_lo.empty()) {
      // One polygon per run of drawable band points.
      std::size_t i = 0;
      const std::size_t n = s.x.size();
      auto good = [&](std::size_t k) {
        return ok(s.x[k], s.band_lo[k]) && ok(s.x[k], s.band_hi[k]);
      };
      while (i < n) {
        while (i < n && !good(i)) ++i;
        std::size_t j = i;
        while (j < n && good(j)) ++j;
        if (j > i) {
          for (std::size_t k = i; k < j; ++k) cairo_line_to(cr, mx(s.x[k]), my(s.band_hi[k]));
          for (std::size_t k = j; k-- > i;) cairo_line_to(cr, mx(s.x[k]), my(s.band_lo[k]));
          cairo_close_path(cr);
          set_color(cr, c, 0.2);
          cairo_fill(cr);
        }
        i = j;
      }
    }
    if (has_line(s.style)) {
      set_line_style(cr, s);
      bool pen = false;
      for (std::size_t i = 0; i < s.x.size(); ++i) {
        if (!ok(s.x[i], s.y[i])) {
          pen = false;
          continue;
        }
        if (pen)
          cairo_line_to(cr, mx(s.x[i]), my(s.y[i]));
        else
          cairo_move_to(cr, mx(s.x[i]), my(s.y[i]));
        pen = true;
      }
      set_color(cr, c);
      cairo_stroke(cr);
    }
    cairo_set_dash(cr, nullptr, 0, 0);
    if (!s.y_err.empty()) {
      cairo_set_line_width(cr, 1);
      const double cap = std::max(2.0, s.marker_size);
      for (std::size_t i = 0; i < s.x.size(); ++i) {
        if (!ok(s.x[i], s.y[i]) || !std::isfinite(s.y_err[i])) continue;
        const double e = std::abs(s.y_err[i]), x = mx(s.x[i]);
        const double yh = my(s.y[i] + e);
        const double yl = drawable(s.y[i] - e, p.y.scale) ? my(s.y[i] - e) : Y0;
        cairo_move_to(cr, x, yl);
        cairo_line_to(cr, x, yh);
        cairo_move_to(cr, x - cap, yh);
        cairo_line_to(cr, x + cap, yh);
        if (yl != Y0) {
          cairo_move_to(cr, x - cap, yl);
          cairo_line_to(cr, x + cap, yl);
        }
      }
      set_color(cr, c);
      cairo_stroke(cr);
    }
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!ok(s.x[i], s.y[i])) continue;
      const double x = mx(s.x[i]), y = my(s.y[i]);
      if (has_markers(s.style)) marker_path(cr, s.marker, x, y, s.marker_size);
    }
    if (has_markers(s.style)) {
      set_color(cr, c);
      cairo_fill(cr);
    }
  }
  cairo_restore(cr);

  // Legend.
  if (legend) {
    cairo_set_font_size(cr, 0.9 * fs);
    const double pad = lpad, row = lrow;
    auto [lx, ly] = corner(place);
    cairo_rectangle(cr, lx, ly, bw, bh);
    cairo_set_source_rgba(cr, 1, 1, 1, 0.88);
    cairo_fill_preserve(cr);
    cairo_set_source_rgb(cr, 0.75, 0.75, 0.75);
    cairo_set_line_width(cr, 1);
    cairo_stroke(cr);
    for (std::size_t k = 0; k < entries.size(); ++k) {
      const auto& s = p.series[entries[k]];
      const PlotColor c = s.color.value_or(plot_palette(entries[k]));
      const double y = ly + pad + row * (static_cast<double>(k) + 0.5);
      if (!s.band_lo.empty() && !has_line(s.style)) {
        cairo_rectangle(cr, lx + pad, y - 0.3 * fs, sample, 0.6 * fs);
        set_color(cr, c, 0.2);
        cairo_fill(cr);
      }
      if (has_line(s.style)) {
        set_line_style(cr, s);
        cairo_move_to(cr, lx + pad, y);
        cairo_line_to(cr, lx + pad + sample, y);
        set_color(cr, c);
        cairo_stroke(cr);
        cairo_set_dash(cr, nullptr, 0, 0);
      }
      if (has_markers(s.style) || !s.y_err.empty()) {
        marker_path(cr, s.marker, lx + pad + 0.5 * sample, y, s.marker_size);
        set_color(cr, c);
        cairo_fill(cr);
      }
      cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
      draw_text(cr, s.label, lx + pad + sample + pad, y, 0, 0.5);
    }
  }
  cairo_restore(cr);
}

std::string lower_ext(const std::string& path) {
  auto dot = path.find_last_of('.');
  auto slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string e = path.substr(dot + 1);
  for (auto& ch : e) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return e;
}

std::string xml_escape(const std::string& s) { return detail::markup_escape(s); }

// What the SVG's <title>/<desc> say (text a browser can search; Cairo outlines the glyphs).
std::pair<std::string, std::string> describe(const std::vector<const Plot*>& plots) {
  std::string title, desc;
  for (const Plot* p : plots) {
    if (!title.empty()) title += "; ";
    title += p->title;
    if (!desc.empty()) desc += "\n";
    desc += (p->title.empty() ? std::string("plot") : p->title) + ". x: " + p->x.label +
            (p->x.scale == AxisScale::Log ? " (log)" : "") + "; y: " + p->y.label +
            (p->y.scale == AxisScale::Log ? " (log)" : "");
    std::string names;
    for (const auto& s : p->series)
      if (!s.label.empty()) names += (names.empty() ? "" : ", ") + s.label;
    if (!names.empty()) desc += "; series: " + names;
  }
  return {title, desc};
}

void check_status(cairo_surface_t* s, const std::string& path) {
  auto st = cairo_surface_status(s);
  if (st != CAIRO_STATUS_SUCCESS)
    throw FileError(path, std::string("cannot write: ") + cairo_status_to_string(st));
}

// Renders the plots (already prepared) in a grid of cells to `path` (PNG or SVG).
void render(const std::vector<const Plot*>& plots, const std::vector<Prepared>& prep,
            std::size_t columns, const std::string& path, const std::string& ext, int cw, int ch) {
  if (cw < 1 || ch < 1 || cw > 20000 || ch > 20000)
    throw InputError("plot size must be 1..20000 pixels");
  detail::load_cairo();
  const std::size_t rows = (plots.size() + columns - 1) / columns;
  const int W = cw * static_cast<int>(std::min(columns, plots.size()));
  const int H = ch * static_cast<int>(rows);
  AtomicFile out(path);
  SurfacePtr surf(ext == "png" ? cairo_image_surface_create(CAIRO_FORMAT_ARGB32, W, H)
                               : cairo_svg_surface_create(out.temp_path().c_str(), W, H));
  check_status(surf.get(), path);
  {
    CairoPtr cr(cairo_create(surf.get()));
    cairo_set_source_rgb(cr.get(), 1, 1, 1);
    cairo_paint(cr.get());
    for (std::size_t i = 0; i < plots.size(); ++i) {
      cairo_save(cr.get());
      cairo_translate(cr.get(), static_cast<double>((i % columns) * static_cast<std::size_t>(cw)),
                      static_cast<double>((i / columns) * static_cast<std::size_t>(ch)));
      cairo_rectangle(cr.get(), 0, 0, cw, ch);
      cairo_clip(cr.get());
      draw_plot(cr.get(), *plots[i], prep[i], cw, ch);
      cairo_restore(cr.get());
    }
    auto st = cairo_status(cr.get());
    if (st != CAIRO_STATUS_SUCCESS)
      throw FileError(path, std::string("drawing failed: ") + cairo_status_to_string(st));
  }
  if (ext == "png") {
    auto st = cairo_surface_write_to_png(surf.get(), out.temp_path().c_str());
    if (st != CAIRO_STATUS_SUCCESS)
      throw FileError(path, std::string("cannot write: ") + cairo_status_to_string(st));
  } else {
    cairo_surface_finish(surf.get());
    check_status(surf.get(), path);
    surf.reset();
    // Add <title> and <desc> right after the opening <svg ...> tag.
    std::string svg;
    {
      std::ifstream in(out.temp_path(), std::ios::binary);
      if (!in) throw FileError(path, "cannot read back the SVG just written");
      svg.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    auto open = svg.find("<svg");
    auto close = open == std::string::npos ? open : svg.find('>', open);
    if (close == std::string::npos)
      throw FileError(path, "Cairo wrote an SVG without an <svg> element");
    auto [t, d] = describe(plots);
    svg.insert(close + 1,
               "\n<title>" + xml_escape(t) + "</title>\n<desc>" + xml_escape(d) + "</desc>");
    std::ofstream o(out.temp_path(), std::ios::binary | std::ios::trunc);
    o << svg;
    o.flush();
    if (!o) throw FileError(path, write_failure_problem(errno));
  }
  out.commit();
}

std::string format_of(const std::string& path) {
  const std::string ext = lower_ext(path);
  if (ext != "png" && ext != "svg")
    throw InputError(path + ": plots are written as .png or .svg (got \"" + ext + "\")");
  return ext;
}

}  // namespace

void Plot::write_png(const std::string& path, int width, int height) const {
  std::vector<Prepared> prep{prepare(*this)};
  render({this}, prep, 1, path, "png", width, height);
}

void Plot::write_svg(const std::string& path, int width, int height) const {
  std::vector<Prepared> prep{prepare(*this)};
  render({this}, prep, 1, path, "svg", width, height);
}

void Plot::write(const std::string& path, int width, int height) const {
  const std::string fmt = format_of(path);
  std::vector<Prepared> prep{prepare(*this)};
  render({this}, prep, 1, path, fmt, width, height);
}

void write_plot_grid(const std::vector<Plot>& plots, std::size_t columns, const std::string& path,
                     int cell_width, int cell_height) {
  if (plots.empty()) throw InputError(path + ": a plot grid needs at least one plot");
  if (columns == 0) throw InputError(path + ": a plot grid needs at least one column");
  const std::string fmt = format_of(path);
  std::vector<const Plot*> ptrs;
  std::vector<Prepared> prep;
  for (const auto& p : plots) {
    ptrs.push_back(&p);
    prep.push_back(prepare(p));
  }
  render(ptrs, prep, columns, path, fmt, cell_width, cell_height);
}

}  // namespace microbrdf
