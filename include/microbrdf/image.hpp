#pragma once
// 8-bit RGB images a person looks at (previews, plots of tables), the PNG writer and the false-
// colour map every preview uses.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace microbrdf {

/// An 8-bit RGB image, row-major from the top, 3 bytes per pixel.
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

/// The PNG file of an image (8-bit RGB), in memory. `what` names it in errors. Throws FileError
/// for an empty image.
std::vector<std::uint8_t> encode_png(const RgbImage& image, const std::string& what);
/// Writes a PNG atomically. Throws FileError.
void write_png(const std::string& path, const RgbImage& image);

/// Maps t in [0, 1] to a perceptually ordered colour (dark blue -> teal -> yellow).
void false_colour(double t, std::uint8_t rgb[3]);

}  // namespace microbrdf
