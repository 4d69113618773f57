#pragma once
// A tiny 3x5 bitmap font for labels on previews (colour bars, units), so previews need no font
// library. Digits, '.', '-', '+', '/', space and the letters e, m, n, r, s, u, x, D; other
// characters draw as blanks (use font_can_draw() to decide whether a text is worth drawing).

#include <cstdint>
#include <string>

#include "microbrdf/image.hpp"

namespace microbrdf::detail {

/// True if every character of `text` has a glyph.
bool font_can_draw(const std::string& text);

/// Width in pixels of `text` drawn at `scale` (4 * scale per character, no trailing gap).
std::size_t text_width(const std::string& text, int scale);

/// Height in pixels of a line drawn at `scale`.
inline std::size_t text_height(int scale) { return static_cast<std::size_t>(5 * scale); }

/// Draws `text` with its top-left corner at (x0, y0), each font pixel a scale x scale block,
/// clipped to the image.
void draw_text(RgbImage& img, std::size_t x0, std::size_t y0, const std::string& text, int scale,
               std::uint8_t r = 20, std::uint8_t g = 20, std::uint8_t b = 20);

}  // namespace microbrdf::detail
