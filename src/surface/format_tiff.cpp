// TIFF height images, read only (libtiff, reading from memory through TIFFClientOpenExt).
//
// Accepted: one sample per pixel; IEEE float 32/64-bit, signed or unsigned integer 8/16/32-bit;
// strips or tiles; any compression libtiff was built with. The first image (directory) is read.
// Heights are metres (integers too, unscaled) unless the ImageDescription holds "z_unit = <unit>"
// (or "z_unit: <unit>"). NaN/Inf samples are invalid. The file stores no lateral scale: spacing
// comes from the options (required). Row 0 is the first row stored (the top of the image).
//
// Hostile files: libtiff messages go to a per-file handler and end up in the FileError (nothing
// is printed); a single libtiff allocation is capped at 256 MiB; an uncompressed image must fit
// in the file and a compressed one may claim at most 256 samples per file byte (+ 2^16).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "core/byte_reader.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/units.hpp"
#include "surface/formats.hpp"
#include "surface/tiff_runtime.hpp"

namespace microbrdf::detail {
namespace {

struct MemFile {
  Bytes data;
  std::uint64_t pos = 0;
  std::string errors;
};

tmsize_t mem_read(thandle_t h, void* buf, tmsize_t n) {
  auto* f = static_cast<MemFile*>(h);
  if (n <= 0 || f->pos >= f->data.size()) return 0;
  const std::uint64_t avail = f->data.size() - f->pos;
  const std::uint64_t k = std::min<std::uint64_t>(avail, static_cast<std::uint64_t>(n));
  std::memcpy(buf, f->data.data() + f->pos, static_cast<std::size_t>(k));
  f->pos += k;
  return static_cast<tmsize_t>(k);
}
tmsize_t mem_write(thandle_t, void*, tmsize_t) { return -1; }
toff_t mem_seek(thandle_t h, toff_t off, int whence) {
  auto* f = static_cast<MemFile*>(h);
  std::uint64_t base = 0;
  if (whence == SEEK_CUR)
    base = f->pos;
  else if (whence == SEEK_END)
    base = f->data.size();
  else if (whence != SEEK_SET)
    return static_cast<toff_t>(-1);
  if (off > UINT64_MAX - base) return static_cast<toff_t>(-1);
  f->pos = base + off;
  return f->pos;
}
int mem_close(thandle_t) { return 0; }
toff_t mem_size(thandle_t h) { return static_cast<MemFile*>(h)->data.size(); }
int mem_map(thandle_t, void**, toff_t*) { return 0; }
void mem_unmap(thandle_t, void*, toff_t) {}

int on_error(TIFF*, void* user, const char* module, const char* fmt, va_list ap) {
  auto* f = static_cast<MemFile*>(user);
  if (f->errors.size() < 400) {
    char buf[256];
    std::vsnprintf(buf, sizeof buf, fmt, ap);
    if (!f->errors.empty()) f->errors += "; ";
    if (module && *module) f->errors += std::string(module) + ": ";
    f->errors += buf;
  }
  return 1;  // handled: libtiff prints nothing
}
int on_warning(TIFF*, void*, const char*, const char*, va_list) { return 1; }

struct TiffCloser {
  void operator()(TIFF* t) const { TIFFClose(t); }
};

std::string description_unit(const std::string& desc) {
  auto p = desc.find("z_unit");
  if (p == std::string::npos) return {};
  p += 6;
  while (p < desc.size() && (desc[p] == ' ' || desc[p] == '=' || desc[p] == ':')) ++p;
  std::size_t e = p;
  while (e < desc.size() && !std::isspace(static_cast<unsigned char>(desc[e])) && desc[e] != ';' &&
         desc[e] != ',')
    ++e;
  return desc.substr(p, e - p);
}

double sample(const std::uint8_t* p, std::uint16_t fmt, std::uint16_t bits) {
  switch (fmt) {
    case SAMPLEFORMAT_IEEEFP:
      if (bits == 32) {
        float v;
        std::memcpy(&v, p, 4);
        return v;
      } else {
        double v;
        std::memcpy(&v, p, 8);
        return v;
      }
    case SAMPLEFORMAT_INT:
      if (bits == 8) return static_cast<std::int8_t>(*p);
      if (bits == 16) {
        std::int16_t v;
        std::memcpy(&v, p, 2);
        return v;
      } else {
        std::int32_t v;
        std::memcpy(&v, p, 4);
        return v;
      }
    default:
      if (bits == 8) return *p;
      if (bits == 16) {
        std::uint16_t v;
        std::memcpy(&v, p, 2);
        return v;
      } else {
        std::uint32_t v;
        std::memcpy(&v, p, 4);
        return v;
      }
  }
}

}  // namespace

Surface read_tiff(Bytes data, const std::string& name, const ReadOptions& options) {
  ByteReader r(data, name);
  if (!options.dx) r.fail("the tiff format stores no sample spacing: pass --spacing (e.g. 110nm)");
  load_tiff(name);
  MemFile mf{data, 0, {}};
  auto fail = [&](const std::string& what) {
    r.fail("tiff: " + what + (mf.errors.empty() ? "" : " (libtiff: " + mf.errors + ")"));
  };

  std::unique_ptr<TIFFOpenOptions, void (*)(TIFFOpenOptions*)> opts(TIFFOpenOptionsAlloc(),
                                                                    TIFFOpenOptionsFree);
  if (!opts) r.fail("tiff: out of memory");
  TIFFOpenOptionsSetMaxSingleMemAlloc(opts.get(), tmsize_t{256} << 20);
  TIFFOpenOptionsSetErrorHandlerExtR(opts.get(), on_error, &mf);
  TIFFOpenOptionsSetWarningHandlerExtR(opts.get(), on_warning, &mf);
  std::unique_ptr<TIFF, TiffCloser> tif(TIFFClientOpenExt(name.c_str(), "rm", &mf, mem_read,
                                                          mem_write, mem_seek, mem_close, mem_size,
                                                          mem_map, mem_unmap, opts.get()));
  if (!tif) fail("cannot open (not a TIFF file, or corrupt header)");
  TIFF* t = tif.get();

  std::uint32_t w = 0, h = 0;
  std::uint16_t bits = 0, spp = 0, fmt = 0, comp = 0, planar = 0;
  if (!TIFFGetField(t, TIFFTAG_IMAGEWIDTH, &w) || !TIFFGetField(t, TIFFTAG_IMAGELENGTH, &h))
    fail("no image width/length");
  TIFFGetFieldDefaulted(t, TIFFTAG_BITSPERSAMPLE, &bits);
  TIFFGetFieldDefaulted(t, TIFFTAG_SAMPLESPERPIXEL, &spp);
  TIFFGetFieldDefaulted(t, TIFFTAG_SAMPLEFORMAT, &fmt);
  TIFFGetFieldDefaulted(t, TIFFTAG_COMPRESSION, &comp);
  TIFFGetFieldDefaulted(t, TIFFTAG_PLANARCONFIG, &planar);
  if (spp != 1)
    fail(std::to_string(spp) +
         " samples per pixel (a colour picture?); a height image holds exactly 1 (the height)");
  const bool ok_type = (fmt == SAMPLEFORMAT_IEEEFP && (bits == 32 || bits == 64)) ||
                       ((fmt == SAMPLEFORMAT_INT || fmt == SAMPLEFORMAT_UINT) &&
                        (bits == 8 || bits == 16 || bits == 32));
  if (!ok_type)
    fail("unsupported sample type (format " + std::to_string(fmt) + ", " + std::to_string(bits) +
         " bits); supported: float 32/64, int/uint 8/16/32");
  if (!TIFFIsCODECConfigured(comp)) fail("compression " + std::to_string(comp) + " not supported");
  const std::size_t bps = bits / 8;
  const std::uint64_t cap = comp == COMPRESSION_NONE
                                ? data.size() / bps
                                : 256 * std::uint64_t{data.size()} + (std::uint64_t{1} << 16);
  check_grid(r, w, h, 0, 0);
  if (std::uint64_t{w} * h > cap)
    fail("image " + std::to_string(w) + " x " + std::to_string(h) + " is too large for a " +
         std::to_string(data.size()) + "-byte file");

  check_surface_memory(name, data.size(), std::uint64_t{w} * h);

  Surface s;
  s.nx = w;
  s.ny = h;
  s.dx = *options.dx;
  s.dy = options.dy ? *options.dy : *options.dx;
  s.z.resize(s.nx * s.ny);
  s.valid.assign(s.z.size(), 1);

  if (TIFFIsTiled(t)) {
    std::uint32_t tw = 0, th = 0;
    if (!TIFFGetField(t, TIFFTAG_TILEWIDTH, &tw) || !TIFFGetField(t, TIFFTAG_TILELENGTH, &th) ||
        tw == 0 || th == 0)
      fail("tiled image without tile size");
    if (std::uint64_t{tw} * th > (std::uint64_t{1} << 24)) fail("tiles are absurdly large");
    const tmsize_t ts = TIFFTileSize(t);
    if (ts <= 0 || static_cast<std::uint64_t>(ts) != std::uint64_t{tw} * th * bps)
      fail("unexpected tile size");
    std::vector<std::uint8_t> buf(static_cast<std::size_t>(ts));
    for (std::uint32_t ty = 0; ty < h; ty += th) {
      for (std::uint32_t tx = 0; tx < w; tx += tw) {
        if (TIFFReadTile(t, buf.data(), tx, ty, 0, 0) < 0)
          fail("cannot read the tile at (" + std::to_string(tx) + ", " + std::to_string(ty) + ")");
        const std::uint32_t ny = std::min(th, h - ty), nx = std::min(tw, w - tx);
        for (std::uint32_t y = 0; y < ny; ++y)
          for (std::uint32_t x = 0; x < nx; ++x)
            s.z[std::size_t{ty + y} * w + tx + x] =
                sample(buf.data() + (std::size_t{y} * tw + x) * bps, fmt, bits);
      }
    }
  } else {
    const tmsize_t ls = TIFFScanlineSize(t);
    if (ls <= 0 || static_cast<std::uint64_t>(ls) != std::uint64_t{w} * bps)
      fail("unexpected scanline size");
    std::vector<std::uint8_t> buf(static_cast<std::size_t>(ls));
    for (std::uint32_t y = 0; y < h; ++y) {
      if (TIFFReadScanline(t, buf.data(), y, 0) < 0)
        fail("cannot read row " + std::to_string(y) + " (truncated or corrupt)");
      for (std::uint32_t x = 0; x < w; ++x)
        s.z[std::size_t{y} * w + x] = sample(buf.data() + std::size_t{x} * bps, fmt, bits);
    }
  }

  s.meta.format = "tiff";
  s.meta.z_unit_in_file = std::string("m");
  s.meta.set("tiff_sample_type", std::string(fmt == SAMPLEFORMAT_IEEEFP ? "float"
                                             : fmt == SAMPLEFORMAT_INT  ? "int"
                                                                        : "uint") +
                                     std::to_string(bits));
  char* desc = nullptr;
  std::string unit;
  if (TIFFGetField(t, TIFFTAG_IMAGEDESCRIPTION, &desc) && desc) {
    s.meta.comment = std::string(desc).substr(0, 4096);
    unit = description_unit(s.meta.comment);
  }
  if (!unit.empty() && options.z_scale)
    fail("the ImageDescription gives the heights' unit (z_unit = " + unit.substr(0, 40) +
         ") and --z-scale gives another: give one");
  if (!unit.empty()) {
    const double scale = length_unit_to_metres(unit);
    if (scale == 0) fail("unknown z_unit '" + unit.substr(0, 40) + "' in ImageDescription");
    for (auto& v : s.z) v *= scale;
    s.meta.z_unit_in_file = unit;
  } else if (options.z_scale) {
    for (auto& v : s.z) v *= *options.z_scale;
    s.meta.z_unit_in_file = "--z-scale " + format_length(*options.z_scale);
  } else if (fmt != SAMPLEFORMAT_IEEEFP) {
    // Integer counts have no unit: reading them as metres made a greyscale photograph a
    // surface with an rms height of metres and slopes of 90 deg.
    fail(std::to_string(bits) +
         "-bit integer samples and no height unit (no 'z_unit = nm' or similar in the "
         "ImageDescription): if this is a height map stored as counts, give the height of one "
         "count with --z-scale (e.g. --z-scale 1nm); a photograph or a greyscale picture is not "
         "a height map (profilometers export .x3p, .datx, .sur, .plu, .dat or .gwy)");
  }
  (void)planar;
  return s;
}

}  // namespace microbrdf::detail
