// Environment-map files: Radiance RGBE (our own bounds-checked reader and a flat writer) and
// OpenEXR RGB (the OpenEXR library, as src/surface/format_exr.cpp uses it).
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfThreading.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <mutex>
#include <sstream>

#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/io.hpp"
#include "render/envmap.hpp"

namespace microbrdf::pt {
namespace {

constexpr int kMaxSide = 1 << 15;

/// Reads the text header line by line; every byte read is checked against the buffer.
struct Cursor {
  const std::vector<std::uint8_t>& d;
  const std::string& name;
  std::size_t pos = 0;
  [[noreturn]] void fail(const std::string& why) const { throw FileError(name, "hdr: " + why); }
  std::string line() {
    std::string s;
    while (true) {
      if (pos >= d.size()) fail("truncated header");
      const char c = static_cast<char>(d[pos++]);
      if (c == '\n') return s;
      if (s.size() > 4096) fail("header line longer than 4096 bytes");
      s += c;
    }
  }
  std::uint8_t byte() {
    if (pos >= d.size()) fail("truncated pixel data (at byte " + std::to_string(pos) + ")");
    return d[pos++];
  }
};

float rgbe_component(std::uint8_t m, std::uint8_t e) {
  return e == 0 ? 0.0f : std::ldexp((float(m) + 0.5f), int(e) - (128 + 8));
}

}  // namespace

RgbFloatImage read_radiance_hdr(const std::string& path) {
  return read_radiance_hdr_bytes(read_file_bytes(path, std::uint64_t{1} << 31), path);
}

RgbFloatImage read_radiance_hdr_bytes(const std::vector<std::uint8_t>& data,
                                      const std::string& name) {
  Cursor c{data, name};
  const std::string magic = c.line();
  if (magic.rfind("#?", 0) != 0) c.fail("not a Radiance file (no '#?' signature)");
  bool format_ok = true;
  for (int lines = 0;; ++lines) {
    if (lines > 1000) c.fail("header has more than 1000 lines");
    const std::string l = c.line();
    if (l.empty()) break;
    if (l.rfind("FORMAT=", 0) == 0 && l != "FORMAT=32-bit_rle_rgbe") format_ok = false;
  }
  if (!format_ok) c.fail("only FORMAT=32-bit_rle_rgbe is supported (not XYZE)");
  const std::string res = c.line();
  char ys[3] = {}, xs[3] = {};
  long h = 0, w = 0;
  if (std::sscanf(res.c_str(), "%2s %ld %2s %ld", ys, &h, xs, &w) != 4)
    c.fail("bad resolution line '" + res.substr(0, 60) + "'");
  if (std::string(ys) != "-Y" || std::string(xs) != "+X")
    c.fail("only the standard orientation '-Y H +X W' is supported, got '" + res.substr(0, 60) +
           "'");
  if (w <= 0 || h <= 0 || w > kMaxSide || h > kMaxSide)
    c.fail("image size " + std::to_string(w) + " x " + std::to_string(h) +
           " outside 1..32768 per side");
  // Run-length encoding stores at most 127 equal bytes in 2, so a file cannot hold more pixels
  // than about 64 per byte: refuse headers that claim more (no huge allocation from a tiny file).
  if (std::uint64_t(w) * std::uint64_t(h) > 64 * std::uint64_t(data.size()) + 65536)
    c.fail("claims " + std::to_string(w) + " x " + std::to_string(h) +
           " pixels, more than the file can hold");
  RgbFloatImage img;
  img.width = int(w);
  img.height = int(h);
  img.rgb.resize(std::size_t(w) * h * 3);
  std::vector<std::uint8_t> line(std::size_t(w) * 4);
  for (long y = 0; y < h; ++y) {
    const std::size_t start = c.pos;
    const std::uint8_t b0 = c.byte(), b1 = c.byte(), b2 = c.byte(), b3 = c.byte();
    const bool rle = w >= 8 && w < 32768 && b0 == 2 && b1 == 2 && (b2 & 0x80) == 0;
    if (rle) {
      if (((long(b2) << 8) | b3) != w) c.fail("scanline " + std::to_string(y) + ": width mismatch");
      for (int ch = 0; ch < 4; ++ch) {
        long x = 0;
        while (x < w) {
          std::uint8_t n = c.byte();
          if (n > 128) {
            n -= 128;
            if (x + n > w) c.fail("scanline " + std::to_string(y) + ": run overflows the line");
            const std::uint8_t v = c.byte();
            for (int k = 0; k < n; ++k) line[std::size_t(x++) * 4 + ch] = v;
          } else {
            if (n == 0 || x + n > w)
              c.fail("scanline " + std::to_string(y) + ": bad literal count");
            for (int k = 0; k < n; ++k) line[std::size_t(x++) * 4 + ch] = c.byte();
          }
        }
      }
    } else {
      if (b0 == 1 && b1 == 1 && b2 == 1) c.fail("old-style run-length encoding is not supported");
      c.pos = start;
      for (long x = 0; x < w; ++x)
        for (int ch = 0; ch < 4; ++ch) line[std::size_t(x) * 4 + ch] = c.byte();
    }
    for (long x = 0; x < w; ++x) {
      const std::uint8_t* p = &line[std::size_t(x) * 4];
      float* o = &img.rgb[(std::size_t(y) * w + x) * 3];
      for (int ch = 0; ch < 3; ++ch) o[ch] = rgbe_component(p[ch], p[3]);
    }
  }
  return img;
}

void write_radiance_hdr(const RgbFloatImage& img, const std::string& path) {
  std::string out = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y " + std::to_string(img.height) +
                    " +X " + std::to_string(img.width) + "\n";
  const std::size_t head = out.size();
  out.resize(head + std::size_t(img.width) * img.height * 4);
  for (std::size_t i = 0; i < std::size_t(img.width) * img.height; ++i) {
    const float* p = &img.rgb[i * 3];
    const float m = std::max({p[0], p[1], p[2], 0.0f});
    unsigned char* q = reinterpret_cast<unsigned char*>(&out[head + i * 4]);
    if (!(m > 1e-32f)) {
      q[0] = q[1] = q[2] = q[3] = 0;
      continue;
    }
    int e;
    const float f = std::frexp(m, &e) * 256.0f / m;
    for (int ch = 0; ch < 3; ++ch)
      q[ch] = static_cast<unsigned char>(std::clamp(std::max(p[ch], 0.0f) * f, 0.0f, 255.0f));
    q[3] = static_cast<unsigned char>(e + 128);
  }
  write_file_atomic(path, out);
}

RgbFloatImage read_exr_rgb(const std::string& path) {
  static std::once_flag once;
  std::call_once(once, [] {
    Imf::staticInitialize();
    Imf::Header::setMaxImageSize(kMaxSide, kMaxSide);
    Imf::Header::setMaxTileSize(1 << 14, 1 << 14);
  });
  require_regular_file(path);
  try {
    Imf::InputFile file(path.c_str(), 0);
    const Imf::Header& hdr = file.header();
    const Imath::Box2i dw = hdr.dataWindow();
    const long w = long(dw.max.x) - dw.min.x + 1, h = long(dw.max.y) - dw.min.y + 1;
    if (w <= 0 || h <= 0 || w > kMaxSide || h > kMaxSide)
      throw FileError(path, "exr: data window " + std::to_string(w) + " x " + std::to_string(h) +
                                " outside 1..32768 per side");
    const Imf::ChannelList& ch = hdr.channels();
    const bool rgb = ch.findChannel("R") && ch.findChannel("G") && ch.findChannel("B");
    if (!rgb && !ch.findChannel("Y"))
      throw FileError(path, "exr: an environment map needs R, G, B (or Y) channels");
    RgbFloatImage img;
    img.width = int(w);
    img.height = int(h);
    img.rgb.assign(std::size_t(w) * h * 3, 0.0f);
    Imf::FrameBuffer fb;
    char* base = reinterpret_cast<char*>(img.rgb.data()) -
                 (std::ptrdiff_t(dw.min.y) * w + dw.min.x) * 3 * std::ptrdiff_t(sizeof(float));
    const char* names[3] = {"R", "G", "B"};
    for (int k = 0; k < (rgb ? 3 : 1); ++k)
      fb.insert(rgb ? names[k] : "Y",
                Imf::Slice(Imf::FLOAT, base + k * sizeof(float), 3 * sizeof(float),
                           std::size_t(w) * 3 * sizeof(float)));
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    if (!rgb)
      for (std::size_t i = 0; i < std::size_t(w) * h; ++i)
        img.rgb[i * 3 + 1] = img.rgb[i * 3 + 2] = img.rgb[i * 3];
    return img;
  } catch (const FileError&) {
    throw;
  } catch (const std::exception& e) {
    throw FileError(path, std::string("exr: ") + e.what());
  }
}

}  // namespace microbrdf::pt
