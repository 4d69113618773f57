// Reading OpenEXR files we did not write (core/exr_guard.hpp): header sizes checked before
// OpenEXR parses them, limits set once, an input stream over bytes in memory.
#include "core/exr_guard.hpp"

#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfThreading.h>

#include <cstring>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>

#include "core/byte_reader.hpp"
#include "microbrdf/error.hpp"

namespace microbrdf::detail {

ExrMemIStream::ExrMemIStream(std::span<const std::uint8_t> data, const std::string& name)
    : Imf::IStream(name.c_str()), data_(data) {}

bool ExrMemIStream::read(char c[], int n) {
  if (n < 0 || pos_ > data_.size() || static_cast<std::size_t>(n) > data_.size() - pos_)
    throw std::runtime_error("unexpected end of file (truncated?)");
  std::memcpy(c, data_.data() + pos_, static_cast<std::size_t>(n));
  pos_ += static_cast<std::size_t>(n);
  return pos_ < data_.size();
}

void ExrMemIStream::seekg(uint64_t pos) {
  pos_ = pos > data_.size() ? data_.size() + 1 : static_cast<std::size_t>(pos);
}

namespace {

constexpr int kMaxSide = 1 << 20;
constexpr std::int64_t kMaxCoord = std::int64_t{1} << 30;
constexpr std::uint64_t kMaxSamples = std::uint64_t{1} << 28;

// OpenEXR 3.1 allocates an attribute's claimed size before reading it (a 400-byte file can ask
// for 2 GB), so walk the header(s) first and check every attribute size against the bytes
// that are really there. Layout: magic, version word, then per part a list of attributes
// (name\0 type\0 int32 size, value) closed by an empty name; multi-part files end the list of
// headers with one more empty name.
// OpenEXR 3.1 reads fixed-size attribute types with their own size whatever the declared size
// says, and reads channel lists, previews and string vectors by their content; a mismatch makes
// it lose its place in the header and read garbage sizes. So each value must be exactly what
// its type implies.
void check_attribute_value(const ByteReader& r, const std::string& name, const std::string& type,
                           ByteCursor v) {
  struct Fixed {
    const char* type;
    std::size_t size;
  };
  static constexpr Fixed kFixed[] = {
      {"box2i", 16},
      {"box2f", 16},
      {"v2i", 8},
      {"v2f", 8},
      {"v2d", 16},
      {"v3i", 12},
      {"v3f", 12},
      {"v3d", 24},
      {"int", 4},
      {"float", 4},
      {"double", 8},
      {"compression", 1},
      {"lineOrder", 1},
      {"envmap", 1},
      {"deepImageState", 1},
      {"m33f", 36},
      {"m33d", 72},
      {"m44f", 64},
      {"m44d", 128},
      {"chromaticities", 32},
      {"keycode", 28},
      {"timecode", 8},
      {"rational", 8},
      {"tiledesc", 9},
  };
  auto bad = [&](const std::string& why) {
    r.fail("exr: corrupt header: attribute '" + name.substr(0, 40) + "' (" + type.substr(0, 40) +
           "): " + why);
  };
  for (const auto& f : kFixed) {
    if (type == f.type) {
      if (v.remaining() != f.size)
        bad("size " + std::to_string(v.remaining()) + ", expected " + std::to_string(f.size));
      return;
    }
  }
  if (type == "chlist") {
    while (true) {
      std::string ch = v.cstring(255, "channel name");
      if (ch.empty()) break;
      v.skip(16, "channel description");
    }
    if (v.remaining() != 0) bad("bytes after the channel list");
  } else if (type == "preview") {
    const std::uint64_t w = v.le<std::uint32_t>("preview width");
    const std::uint64_t h = v.le<std::uint32_t>("preview height");
    if (w * h * 4 != v.remaining()) bad("preview size does not match its pixels");
  } else if (type == "stringvector") {
    while (v.remaining() > 0) {
      const std::int32_t n = v.le<std::int32_t>("string length");
      if (n < 0 || static_cast<std::size_t>(n) > v.remaining()) bad("string longer than the value");
      v.skip(static_cast<std::size_t>(n), "string");
    }
  } else if (type == "idmanifest") {
    bad("ID manifests are not supported");
  }
}

void check_exr_headers(const ByteReader& r) {
  ByteCursor c(r, 0);
  if (c.le<std::uint32_t>("magic") != 20000630u) r.fail("exr: not an OpenEXR file (bad magic)");
  const std::uint32_t version = c.le<std::uint32_t>("version");
  const bool multipart = (version & 0x1000u) != 0;
  for (int part = 0;; ++part) {
    if (part > 4096) r.fail("exr: too many parts");
    int attrs = 0;
    while (true) {
      std::string name = c.cstring(255, "attribute name");
      if (name.empty()) break;
      if (++attrs > 100000) r.fail("exr: too many header attributes");
      const std::string type = c.cstring(255, "attribute type");
      const std::int32_t size = c.le<std::int32_t>("attribute size");
      if (size < 0 || static_cast<std::size_t>(size) > c.remaining())
        r.fail("exr: corrupt header: attribute '" + name.substr(0, 40) + "' claims " +
               std::to_string(size) + " bytes, only " + std::to_string(c.remaining()) + " remain");
      check_attribute_value(r, name, type, ByteCursor(r, c.pos(), c.pos() + size));
      c.skip(static_cast<std::size_t>(size), "attribute value");
    }
    if (!multipart) break;
    if (attrs == 0) break;  // the empty header that ends a multi-part header list
  }
}

}  // namespace

void init_openexr_limits() {
  static std::once_flag once;
  std::call_once(once, [] {
    Imf::staticInitialize();
    Imf::Header::setMaxImageSize(kMaxSide, kMaxSide);
    Imf::Header::setMaxTileSize(1 << 14, 1 << 14);
  });
}

void check_exr_header_bytes(std::span<const std::uint8_t> data, const std::string& name) {
  check_exr_headers(ByteReader(data, name));
}

std::uint64_t check_exr_data_window(const Imath::Box2i& dw, std::size_t file_bytes,
                                    const std::string& name) {
  auto absurd = [](int v) { return v < -kMaxCoord || v > kMaxCoord; };
  if (absurd(dw.min.x) || absurd(dw.min.y) || absurd(dw.max.x) || absurd(dw.max.y))
    throw FileError(name, "exr: data window has absurd coordinates");
  const std::int64_t w = std::int64_t{dw.max.x} - dw.min.x + 1;
  const std::int64_t h = std::int64_t{dw.max.y} - dw.min.y + 1;
  if (w <= 0 || h <= 0) throw FileError(name, "exr: empty data window");
  const std::uint64_t cap =
      std::min<std::uint64_t>(kMaxSamples, 256 * std::uint64_t{file_bytes} + (1u << 16));
  const std::uint64_t samples = static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h);
  if (samples > cap)
    throw FileError(name, "exr: data window " + std::to_string(w) + " x " + std::to_string(h) +
                              " is too large for a " + std::to_string(file_bytes) + "-byte file");
  return samples;
}

}  // namespace microbrdf::detail
