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
#include "core/exr_guard.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/units.hpp"
#include "surface/formats.hpp"

namespace microbrdf::detail {

namespace {

Surface read_exr_impl(Bytes data, const ByteReader& r, const ReadOptions& options) {
  if (!options.dx) r.fail("the exr format stores no sample spacing: pass --spacing (e.g. 110nm)");
  check_exr_header_bytes(data, r.name());
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
