// Throwaway generator for the small EXR/TIFF test fixtures in tests/data/ and the fuzz seeds in
// fuzz/corpus/{exr,tiff}/. Not part of the build. Regenerate with:
//   g++ -std=c++20 -O1 tests/data/make_image_fixtures.cpp -o /tmp/make_image_fixtures \
//       $(pkg-config --cflags --libs OpenEXR libtiff-4) && /tmp/make_image_fixtures OUTDIR
// Pixel values follow the formula in expected_height() so tests can check them exactly.
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfTiledOutputFile.h>
#include <tiffio.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

// Height at column ix, row iy (metres before any z_unit scaling); NaN at (3, 2).
static double expected_height(int ix, int iy) {
  if (ix == 3 && iy == 2) return NAN;
  return (ix * 0.25 + iy * 1.5 - 3.0) * 1e-6;
}

static void write_exr(const std::string& path, int w, int h, const char* chan, Imf::PixelType pt,
                      const char* z_unit, Imf::Compression comp, int min_x, int min_y) {
  Imf::Header hdr(Imath::Box2i({0, 0}, {w - 1, h - 1}),
                  Imath::Box2i({min_x, min_y}, {min_x + w - 1, min_y + h - 1}));
  hdr.compression() = comp;
  std::vector<std::string> names;
  if (std::string(chan) == "RGB")
    names = {"R", "G", "B"};
  else
    names = {chan};
  for (auto& n : names) hdr.channels().insert(n, Imf::Channel(pt));
  if (z_unit) hdr.insert("z_unit", Imf::StringAttribute(z_unit));
  hdr.insert("comments", Imf::StringAttribute("microbrdf test fixture"));
  std::vector<float> f(w * h);
  std::vector<Imath::half> hf(w * h);
  std::vector<float> other(w * h, 42.0f);
  std::vector<Imath::half> otherh(w * h, Imath::half(42.0f));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      f[y * w + x] = static_cast<float>(expected_height(x, y));
      hf[y * w + x] = Imath::half(static_cast<float>(x - 2 * y));  // small integers, exact in half
    }
  Imf::FrameBuffer fb;
  for (auto& n : names) {
    bool main = n == names[0];
    if (pt == Imf::HALF)
      fb.insert(n, Imf::Slice::Make(Imf::HALF, main ? hf.data() : otherh.data(), hdr.dataWindow(),
                                    sizeof(Imath::half), w * sizeof(Imath::half)));
    else
      fb.insert(n, Imf::Slice::Make(Imf::FLOAT, main ? f.data() : other.data(), hdr.dataWindow(),
                                    sizeof(float), w * sizeof(float)));
  }
  Imf::OutputFile out(path.c_str(), hdr);
  out.setFrameBuffer(fb);
  out.writePixels(h);
}

static void write_exr_tiled(const std::string& path, int w, int h) {
  Imf::Header hdr(w, h);
  hdr.compression() = Imf::ZIP_COMPRESSION;
  hdr.channels().insert("Z", Imf::Channel(Imf::FLOAT));
  hdr.setTileDescription(Imf::TileDescription(8, 8, Imf::ONE_LEVEL));
  std::vector<float> f(w * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) f[y * w + x] = static_cast<float>(expected_height(x, y));
  Imf::FrameBuffer fb;
  fb.insert("Z", Imf::Slice::Make(Imf::FLOAT, f.data(), hdr.dataWindow(), sizeof(float),
                                  w * sizeof(float)));
  Imf::TiledOutputFile out(path.c_str(), hdr);
  out.setFrameBuffer(fb);
  out.writeTiles(0, out.numXTiles() - 1, 0, out.numYTiles() - 1);
}

static void write_tiff(const std::string& path, int w, int h, int fmt, int bits, int spp, int comp,
                       bool tiled, const char* desc, const char* mode = "w") {
  TIFF* t = TIFFOpen(path.c_str(), mode);
  TIFFSetField(t, TIFFTAG_IMAGEWIDTH, w);
  TIFFSetField(t, TIFFTAG_IMAGELENGTH, h);
  TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, bits);
  TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, spp);
  TIFFSetField(t, TIFFTAG_SAMPLEFORMAT, fmt);
  TIFFSetField(t, TIFFTAG_PHOTOMETRIC, spp == 3 ? PHOTOMETRIC_RGB : PHOTOMETRIC_MINISBLACK);
  TIFFSetField(t, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
  TIFFSetField(t, TIFFTAG_COMPRESSION, comp);
  if (desc) TIFFSetField(t, TIFFTAG_IMAGEDESCRIPTION, desc);
  const int bps = bits / 8 * spp;
  auto value = [&](int x, int y, std::uint8_t* p) {
    for (int s = 0; s < spp; ++s, p += bits / 8) {
      if (fmt == SAMPLEFORMAT_IEEEFP && bits == 64) {
        double v = expected_height(x, y);
        memcpy(p, &v, 8);
      } else if (fmt == SAMPLEFORMAT_IEEEFP) {
        float v = static_cast<float>(expected_height(x, y));
        memcpy(p, &v, 4);
      } else if (bits == 32) {
        std::int32_t v = -5000 + 7 * x + 300 * y;
        memcpy(p, &v, 4);
      } else if (bits == 8) {
        *p = static_cast<std::uint8_t>(x + 10 * y);
      } else {
        std::uint16_t v = static_cast<std::uint16_t>(1000 + 7 * x + 300 * y);
        memcpy(p, &v, 2);
      }
    }
  };
  if (tiled) {
    TIFFSetField(t, TIFFTAG_TILEWIDTH, 16);
    TIFFSetField(t, TIFFTAG_TILELENGTH, 16);
    std::vector<std::uint8_t> tile(16 * 16 * bps, 0);
    for (int ty = 0; ty < h; ty += 16)
      for (int tx = 0; tx < w; tx += 16) {
        for (int y = 0; y < 16; ++y)
          for (int x = 0; x < 16; ++x)
            if (ty + y < h && tx + x < w) value(tx + x, ty + y, &tile[(y * 16 + x) * bps]);
        TIFFWriteTile(t, tile.data(), tx, ty, 0, 0);
      }
  } else {
    TIFFSetField(t, TIFFTAG_ROWSPERSTRIP, 4);
    std::vector<std::uint8_t> row(w * bps);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) value(x, y, &row[x * bps]);
      TIFFWriteScanline(t, row.data(), y, 0);
    }
  }
  TIFFClose(t);
}

int main(int argc, char** argv) {
  std::string d = argc > 1 ? argv[1] : ".";
  // test fixtures
  write_exr(d + "/height_z_float.exr", 20, 12, "Z", Imf::FLOAT, nullptr, Imf::ZIP_COMPRESSION, 5,
            -3);
  write_exr(d + "/height_rgb_half_um.exr", 10, 6, "RGB", Imf::HALF, "um", Imf::NO_COMPRESSION, 0,
            0);
  write_exr_tiled(d + "/height_z_tiled.exr", 20, 12);
  write_tiff(d + "/height_f32.tif", 20, 12, SAMPLEFORMAT_IEEEFP, 32, 1, COMPRESSION_ADOBE_DEFLATE,
             false, "microbrdf test fixture");
  write_tiff(d + "/height_f32_tiled.tif", 20, 12, SAMPLEFORMAT_IEEEFP, 32, 1, COMPRESSION_NONE,
             true, nullptr);
  write_tiff(d + "/height_u16_nm.tif", 20, 12, SAMPLEFORMAT_UINT, 16, 1, COMPRESSION_LZW, false,
             "z_unit = nm");
  write_tiff(d + "/height_rgb16.tif", 4, 3, SAMPLEFORMAT_UINT, 16, 3, COMPRESSION_NONE, false,
             nullptr);
  // fuzz seeds (second argument: a directory holding exr/ and tiff/)
  if (argc > 2) {
    std::string f = argv[2];
    write_exr(f + "/exr/z_float_zip.exr", 20, 12, "Z", Imf::FLOAT, nullptr, Imf::ZIP_COMPRESSION, 5,
              -3);
    write_exr(f + "/exr/rgb_half_um.exr", 10, 6, "RGB", Imf::HALF, "um", Imf::NO_COMPRESSION, 0, 0);
    write_exr(f + "/exr/z_float_piz.exr", 8, 8, "Z", Imf::FLOAT, nullptr, Imf::PIZ_COMPRESSION, 0,
              0);
    write_exr(f + "/exr/z_float_pxr24.exr", 8, 8, "Z", Imf::FLOAT, nullptr, Imf::PXR24_COMPRESSION,
              0, 0);
    write_exr(f + "/exr/z_float_rle.exr", 8, 8, "Z", Imf::FLOAT, nullptr, Imf::RLE_COMPRESSION, 0,
              0);
    write_exr(f + "/exr/y_half_b44.exr", 8, 8, "Y", Imf::HALF, nullptr, Imf::B44_COMPRESSION, 0, 0);
    write_exr(f + "/exr/y_half_dwaa.exr", 8, 8, "Y", Imf::HALF, nullptr, Imf::DWAA_COMPRESSION, 0,
              0);
    write_exr_tiled(f + "/exr/z_float_tiled_zip.exr", 20, 12);
    write_tiff(f + "/tiff/f32_deflate.tif", 20, 12, SAMPLEFORMAT_IEEEFP, 32, 1,
               COMPRESSION_ADOBE_DEFLATE, false, "seed");
    write_tiff(f + "/tiff/f32_tiled.tif", 20, 12, SAMPLEFORMAT_IEEEFP, 32, 1, COMPRESSION_NONE,
               true, nullptr);
    write_tiff(f + "/tiff/u16_lzw_nm.tif", 20, 12, SAMPLEFORMAT_UINT, 16, 1, COMPRESSION_LZW, false,
               "z_unit = nm");
    write_tiff(f + "/tiff/f64_packbits.tif", 6, 5, SAMPLEFORMAT_IEEEFP, 64, 1, COMPRESSION_PACKBITS,
               false, nullptr);
    write_tiff(f + "/tiff/i32_bigendian.tif", 6, 5, SAMPLEFORMAT_INT, 32, 1, COMPRESSION_NONE,
               false, nullptr, "wb");
    write_tiff(f + "/tiff/u8.tif", 6, 5, SAMPLEFORMAT_UINT, 8, 1, COMPRESSION_NONE, false, nullptr);
  }
  return 0;
}
