// 8-bit RGB images: the false-colour map and the PNG writer (include/microbrdf/image.hpp).
#include "microbrdf/image.hpp"

#include <png.h>

#include <algorithm>
#include <cmath>

#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"

namespace microbrdf {

void false_colour(double t, std::uint8_t rgb[3]) {
  // Piecewise-linear through hand-picked anchors, monotone in lightness.
  static constexpr double kAnchors[][3] = {{0.10, 0.05, 0.30}, {0.15, 0.30, 0.60},
                                           {0.10, 0.55, 0.60}, {0.35, 0.75, 0.45},
                                           {0.80, 0.85, 0.25}, {0.99, 0.95, 0.60}};
  constexpr int n = 6;
  t = std::clamp(t, 0.0, 1.0) * (n - 1);
  int i = std::min(static_cast<int>(t), n - 2);
  double f = t - i;
  for (int c = 0; c < 3; ++c)
    rgb[c] = static_cast<std::uint8_t>(
        std::lround(255 * ((1 - f) * kAnchors[i][c] + f * kAnchors[i + 1][c])));
}

namespace {
void append_bytes(png_structp png, png_bytep data, png_size_t n) {
  auto* out = static_cast<std::vector<std::uint8_t>*>(png_get_io_ptr(png));
  out->insert(out->end(), data, data + n);
}
void no_flush(png_structp) {}

// The libpng calls, apart: nothing in this frame lives across setjmp but the two handles.
void encode_into(const RgbImage& image, const std::string& what, std::vector<std::uint8_t>& out) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, &info);
    throw FileError(what, "libpng initialisation failed");
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw FileError(what, "PNG encoding failed");
  }
  png_set_write_fn(png, &out, &append_bytes, &no_flush);
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.width),
               static_cast<png_uint_32>(image.height), 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  // zlib level 3 instead of libpng's 6: a third of the CPU, files a few per cent larger.
  png_set_compression_level(png, 3);
  png_write_info(png, info);
  for (std::size_t y = 0; y < image.height; ++y)
    png_write_row(png, const_cast<png_bytep>(&image.pixels[y * image.width * 3]));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
}
}  // namespace

std::vector<std::uint8_t> encode_png(const RgbImage& image, const std::string& what) {
  if (image.width == 0 || image.height == 0) throw FileError(what, "cannot write an empty image");
  std::vector<std::uint8_t> out;
  encode_into(image, what, out);
  return out;
}

void write_png(const std::string& path, const RgbImage& image) {
  write_file_atomic(path, encode_png(image, path));
}

}  // namespace microbrdf
