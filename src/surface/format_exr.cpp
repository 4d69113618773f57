// OpenEXR height images, read only (OpenEXR 3 C++ API, reading from memory).
//
// Channel: "Z", else "Y", else "R", else the first channel in the file (alphabetical order).
// FLOAT and HALF channels are read as float, UINT as uint32; subsampled channels are refused.
// Heights are metres unless a string attribute "z_unit" names another length unit. NaN/Inf
// samples are invalid. The file stores no lateral scale: spacing comes from the options
// (required). Row 0 is the top row of the data window (the first row stored).
//
// Limits (hostile files): every header attribute size is checked against the file before
// OpenEXR parses the header (it would allocate the claimed size); width and height of the data
// window at most 2^20 (enforced by OpenEXR's own header sanity check), data-window corners within
// +-2^30, and at most min(2^28, 256 * file size + 2^16) samples, so a tiny compressed file cannot
// make us allocate gigabytes.
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfThreading.h>

#include <cmath>
#include <cstring>
#include <exception>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

#include "core/byte_reader.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/units.hpp"
#include "surface/exr_guard.hpp"
#include "surface/formats.hpp"

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

namespace {

Surface read_exr_impl(Bytes data, const ByteReader& r, const ReadOptions& options) {
  if (!options.dx) r.fail("the exr format stores no sample spacing: pass --spacing (e.g. 110nm)");
  check_exr_headers(r);
  ExrMemIStream stream(data, r.name());
  Imf::InputFile file(stream, 0);  // 0 = no worker threads
  const Imf::Header& hdr = file.header();
  const Imath::Box2i dw = hdr.dataWindow();
  check_exr_data_window(dw, data.size(), r.name());
  const std::int64_t w = std::int64_t{dw.max.x} - dw.min.x + 1;
  const std::int64_t h = std::int64_t{dw.max.y} - dw.min.y + 1;
  check_grid(r, static_cast<std::uint64_t>(w), static_cast<std::uint64_t>(h), 0, 0);

  const Imf::ChannelList& channels = hdr.channels();
  const char* chosen = nullptr;
  for (const char* want : {"Z", "Y", "R"})
    if (channels.findChannel(want)) {
      chosen = want;
      break;
    }
  std::string first;
  if (!chosen) {
    auto it = channels.begin();
    if (it == channels.end()) r.fail("exr: the file has no channels");
    first = it.name();
    chosen = first.c_str();
  }
  const Imf::Channel& ch = *channels.findChannel(chosen);
  if (ch.xSampling != 1 || ch.ySampling != 1)
    r.fail(std::string("exr: channel '") + chosen + "' is subsampled; not supported");

  double zscale = 1.0;
  std::string zunit = "m";
  if (const auto* a = hdr.findTypedAttribute<Imf::StringAttribute>("z_unit")) {
    zunit = a->value();
    zscale = length_unit_to_metres(zunit);
    if (zscale == 0) r.fail("exr: unknown z_unit '" + zunit.substr(0, 40) + "'");
  }

  // Heights, mask and the 4-byte pixel buffer OpenEXR decodes into.
  check_surface_memory(r.name(), data.size(), static_cast<std::uint64_t>(w) * h,
                       static_cast<std::uint64_t>(w) * h * 4);
  const auto nx = static_cast<std::size_t>(w), ny = static_cast<std::size_t>(h);
  Surface s;
  s.nx = nx;
  s.ny = ny;
  s.dx = *options.dx;
  s.dy = options.dy ? *options.dy : *options.dx;
  s.z.resize(nx * ny);
  s.valid.assign(nx * ny, 1);
  Imf::FrameBuffer fb;
  if (ch.type == Imf::UINT) {
    std::vector<std::uint32_t> buf(nx * ny, 0);
    fb.insert(chosen, Imf::Slice::Make(Imf::UINT, buf.data(), dw, sizeof(std::uint32_t),
                                       nx * sizeof(std::uint32_t)));
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    for (std::size_t i = 0; i < buf.size(); ++i) s.z[i] = static_cast<double>(buf[i]) * zscale;
  } else {
    std::vector<float> buf(nx * ny, std::numeric_limits<float>::quiet_NaN());
    fb.insert(chosen,
              Imf::Slice::Make(Imf::FLOAT, buf.data(), dw, sizeof(float), nx * sizeof(float), 1, 1,
                               std::numeric_limits<double>::quiet_NaN()));
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    for (std::size_t i = 0; i < buf.size(); ++i) s.z[i] = static_cast<double>(buf[i]) * zscale;
  }
  s.meta.format = "exr";
  s.meta.z_unit_in_file = zunit;
  s.meta.set("exr_channel", chosen);
  s.meta.set("exr_channel_type", ch.type == Imf::UINT   ? "uint32"
                                 : ch.type == Imf::HALF ? "half"
                                                        : "float");
  if (const auto* a = hdr.findTypedAttribute<Imf::StringAttribute>("comments"))
    s.meta.comment = a->value();
  return s;
}

}  // namespace

Surface read_exr(Bytes data, const std::string& name, const ReadOptions& options) {
  ByteReader r(data, name);
  init_openexr_limits();
  try {
    return read_exr_impl(data, r, options);
  } catch (const FileError&) {
    throw;
  } catch (const std::bad_alloc&) {
    r.fail("exr: out of memory while reading (corrupt header?; --max-memory)");
  } catch (const std::exception& e) {
    r.fail(std::string("exr: ") + e.what());
  }
}

}  // namespace microbrdf::detail
