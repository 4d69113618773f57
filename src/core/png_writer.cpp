#include <png.h>

#include <cstdio>
#include <memory>

#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/preview.hpp"

namespace microbrdf {

void write_png(const std::string& path, const RgbImage& image) {
  if (image.width == 0 || image.height == 0) throw FileError(path, "cannot write an empty image");
  AtomicFile out(path);
  {
    std::unique_ptr<FILE, int (*)(FILE*)> fp(std::fopen(out.temp_path().c_str(), "wb"),
                                             &std::fclose);
    if (!fp) throw FileError(path, "cannot create file");
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (!png || !info) {
      png_destroy_write_struct(&png, &info);
      throw FileError(path, "libpng initialisation failed");
    }
    if (setjmp(png_jmpbuf(png))) {
      png_destroy_write_struct(&png, &info);
      throw FileError(path, "PNG write failed (disk full?)");
    }
    png_init_io(png, fp.get());
    png_set_IHDR(png, info, static_cast<png_uint_32>(image.width),
                 static_cast<png_uint_32>(image.height), 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (std::size_t y = 0; y < image.height; ++y)
      png_write_row(png, const_cast<png_bytep>(&image.pixels[y * image.width * 3]));
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
  }
  out.commit();
}

}  // namespace microbrdf
