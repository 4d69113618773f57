// 3x5 bitmap font (see bitmap_font.hpp). Each glyph is 15 bits, rows top to bottom, 3 bits per
// row, most significant bit = top-left pixel.
#include "core/bitmap_font.hpp"

namespace microbrdf::detail {
namespace {

struct Glyph {
  char ch;
  std::uint16_t bits;
};

constexpr Glyph kGlyphs[] = {
    {'0', 0x7B6F}, {'1', 0x2C97}, {'2', 0x73E7}, {'3', 0x73CF}, {'4', 0x5BC9}, {'5', 0x79CF},
    {'6', 0x79EF}, {'7', 0x7249}, {'8', 0x7BEF}, {'9', 0x7BCF}, {'.', 0x0002}, {'-', 0x01C0},
    {'+', 0x05D0}, {'/', 0x12A4}, {' ', 0x0000}, {'n', 0x0D6D},  // ... ##. #.# #.# #.#
    {'m', 0x0FED},                                               // ... ### ### #.# #.#
    {'u', 0x0B6F},                                               // mu: ... #.# #.# #.# ###
    {'e', 0x0DE3},                                               // ... ##. ### #.. .##
    {'r', 0x0BA4},                                               // ... #.# ##. #.. #..
    {'s', 0x070E},                                               // ... .## #.. ..# ##.
    {'x', 0x0AAD},                                               // ... #.# .#. #.# #.#
    {'D', 0x6B6E},                                               // ##. #.# #.# #.# ##.
};

const Glyph* find(char ch) {
  for (const auto& g : kGlyphs)
    if (g.ch == ch) return &g;
  return nullptr;
}

}  // namespace

bool font_can_draw(const std::string& text) {
  for (char ch : text)
    if (!find(ch)) return false;
  return true;
}

std::size_t text_width(const std::string& text, int scale) {
  if (text.empty()) return 0;
  return static_cast<std::size_t>(4 * scale) * text.size() - static_cast<std::size_t>(scale);
}

void draw_text(RgbImage& img, std::size_t x0, std::size_t y0, const std::string& text, int scale,
               std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  std::size_t x = x0;
  for (char ch : text) {
    const Glyph* glyph = find(ch);
    const std::uint16_t bits = glyph ? glyph->bits : 0;
    for (int row = 0; row < 5; ++row)
      for (int col = 0; col < 3; ++col) {
        if (!((bits >> (14 - (row * 3 + col))) & 1)) continue;
        for (int sy = 0; sy < scale; ++sy)
          for (int sx = 0; sx < scale; ++sx) {
            std::size_t px = x + static_cast<std::size_t>(col * scale + sx);
            std::size_t py = y0 + static_cast<std::size_t>(row * scale + sy);
            if (px < img.width && py < img.height) img.set(px, py, r, g, b);
          }
      }
    x += static_cast<std::size_t>(4 * scale);
  }
}

}  // namespace microbrdf::detail
