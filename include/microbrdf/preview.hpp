#pragma once
// 8-bit previews a person looks at: height maps in false colour with a scale bar, written as
// PNG (atomically).

#include <cstdint>
#include <string>
#include <vector>

#include "microbrdf/surface.hpp"

namespace microbrdf {

/// An 8-bit RGB image, row-major, 3 bytes per pixel.
struct RgbImage {
  std::size_t width = 0, height = 0;
  std::vector<std::uint8_t> pixels;
  RgbImage() = default;
  RgbImage(std::size_t w, std::size_t h) : width(w), height(h), pixels(w * h * 3, 0) {}
  void set(std::size_t x, std::size_t y, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
    auto* p = &pixels[(y * width + x) * 3];
    p[0] = r;
    p[1] = g;
    p[2] = b;
  }
};

/// Writes a PNG atomically. Throws FileError.
void write_png(const std::string& path, const RgbImage& image);

/// Maps t in [0, 1] to a perceptually ordered colour (dark blue -> teal -> yellow).
void false_colour(double t, std::uint8_t rgb[3]);

/// Height-map preview: heights between the 0.5th and 99.5th percentile mapped to false colour
/// with light hill-shading, invalid samples grey; at most `max_size` pixels on the long side
/// (box-filtered), row 0 at the top, and a colour bar with the height range on the right.
RgbImage render_height_preview(const Surface& s, std::size_t max_size = 1024);

}  // namespace microbrdf
