#pragma once
// Text labels on raster previews (colour bars, units, titles): drawn with Cairo in DejaVu Sans
// (anti-aliased outline-font text, the face of the SVG plots), not a pixel font. `scale` sets the
// size: digits and capitals are about 5 * scale pixels tall. (The file keeps its old name: it
// held a 3x5 bitmap font before.)

#include <cstdint>
#include <string>

#include "microbrdf/image.hpp"

namespace microbrdf::detail {

/// True for any text (every character is drawn by the font; kept for callers that used to ask).
bool font_can_draw(const std::string& text);

/// Advance width in pixels of `text` drawn at `scale` (rounded up).
std::size_t text_width(const std::string& text, int scale);

/// Height in pixels of digits and capitals drawn at `scale` (descenders reach about a quarter
/// of it lower).
inline std::size_t text_height(int scale) { return static_cast<std::size_t>(5 * scale); }

/// Draws `text` (UTF-8) with the top of its digits/capitals at y0 and its left edge at x0,
/// blended over the image, clipped to it.
void draw_text(RgbImage& img, std::size_t x0, std::size_t y0, const std::string& text, int scale,
               std::uint8_t r = 20, std::uint8_t g = 20, std::uint8_t b = 20);

}  // namespace microbrdf::detail
