// Format dispatch: extension / magic detection, file loading with a size cap, npy sidecars,
// atomic writes.
#include "microbrdf/io.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <vector>

#include "core/length_text.hpp"
#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/json_read.hpp"
#include "microbrdf/memory_budget.hpp"
#include "surface/formats.hpp"

namespace microbrdf {
namespace fs = std::filesystem;

namespace {

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext;
}

struct FormatInfo {
  SurfaceFormat format;
  const char* name;
  bool can_write;
  bool needs_spacing;
};

constexpr FormatInfo kFormats[] = {
    {SurfaceFormat::X3p, "x3p", true, false},
    {SurfaceFormat::MetroProDat, "dat", false, false},
    {SurfaceFormat::Datx, "datx", false, false},
    {SurfaceFormat::Sur, "sur", false, false},
    {SurfaceFormat::Plu, "plu", false, false},
    {SurfaceFormat::Gwy, "gwy", true, false},
    {SurfaceFormat::AsciiXyz, "xyz", true, false},
    {SurfaceFormat::AsciiGrid, "txt", true, true},
    {SurfaceFormat::Npy, "npy", true, true},
    {SurfaceFormat::Exr, "exr", false, true},
    {SurfaceFormat::Tiff, "tiff", false, true},
};

const FormatInfo& info(SurfaceFormat f) {
  for (const auto& i : kFormats)
    if (i.format == f) return i;
  throw InputError("no such surface format");
}

// Spacing (and origin) for a .npy from its JSON sidecar (scan.npy + scan.json), if present.
void read_npy_sidecar(const std::string& path, ReadOptions& opt, double& x0, double& y0) {
  fs::path side = fs::path(path).replace_extension(".json");
  if (!fs::exists(side)) return;
  const nlohmann::json j = read_json_file(side.string());
  auto get = [&](const char* key) -> std::optional<double> {
    if (!j.contains(key)) return std::nullopt;
    if (!j[key].is_number() || !(j[key].get<double>() > 0))
      throw FileError(side.string(),
                      std::string("'") + key + "' must be a positive number (metres)");
    return j[key].get<double>();
  };
  if (!opt.dx) opt.dx = get("dx_m");
  if (!opt.dy) opt.dy = get("dy_m");
  for (auto [key, out] : {std::pair{"x0_m", &x0}, std::pair{"y0_m", &y0}}) {
    if (!j.contains(key)) continue;
    if (!j[key].is_number())
      throw FileError(side.string(), std::string("'") + key + "' must be a number (metres)");
    *out = j[key].get<double>();
  }
  if (opt.dx && !opt.dy) opt.dy = opt.dx;
}

void write_npy_sidecar(const Surface& s, const std::string& path) {
  fs::path side = fs::path(path).replace_extension(".json");
  nlohmann::json j = {{"dx_m", s.dx},
                      {"dy_m", s.dy},
                      {"x0_m", s.x0},
                      {"y0_m", s.y0},
                      {"z_unit", "m"},
                      {"invalid", "NaN"},
                      {"leveling", s.meta.leveling},
                      {"source", s.meta.source_path}};
  write_file_atomic(side.string(), j.dump(2) + "\n");
}

// Heights beyond 1e12 m are corrupt data: refusing them here keeps squares and sums of heights
// finite everywhere downstream (1e308 squared is inf). The bound leaves room for integer files
// that store raw counts (up to 2^32) as heights.
constexpr double kMaxAbsHeight = 1e12;
constexpr double kMaxSpacing = 1.0;
// No instrument samples a surface finer than 1 pm (a hundredth of an atom); with heights bounded
// by 1e12 m this also keeps every slope (height difference / spacing) and its square finite.
constexpr double kMinSpacing = 1e-12;

// The kind of picture `h` starts with (PNG, JPEG, GIF, BMP), or nullptr: pictures are what a
// user most often mistakes for a height map.
const char* picture_format(std::span<const std::uint8_t> h) {
  auto starts = [&](std::initializer_list<std::uint8_t> m) {
    return h.size() >= m.size() && std::equal(m.begin(), m.end(), h.begin());
  };
  if (starts({0x89, 'P', 'N', 'G'})) return "PNG";
  if (starts({0xFF, 0xD8, 0xFF})) return "JPEG";
  if (starts({'G', 'I', 'F', '8'})) return "GIF";
  if (starts({'B', 'M'}) && h.size() > 26) return "BMP";
  return nullptr;
}

void check_heights(const Surface& s, const std::string& name) {
  for (std::size_t iy = 0; iy < s.ny; ++iy)
    for (std::size_t ix = 0; ix < s.nx; ++ix) {
      const std::size_t i = iy * s.nx + ix;
      if (s.valid[i] && !(std::abs(s.z[i]) <= kMaxAbsHeight)) {
        char v[32];
        std::snprintf(v, sizeof v, "%g", s.z[i]);
        throw FileError(name, std::string("height ") + v + " m at sample (x " + std::to_string(ix) +
                                  ", y " + std::to_string(iy) +
                                  ") is absurd (beyond 1e12 m): corrupt data or a wrong unit");
      }
    }
}

// The median slope between neighbouring samples (along x, on a subset of at most ~65536 pairs):
// above 1000 (89.94 deg) the heights cannot be a surface at this spacing. A genuine surface,
// however rough, has most of its slopes far below that; a picture read as heights (counts or
// 0..1 grey values as metres at a micrometre spacing) has slopes of 10^4 to 10^7.
void check_plausible_slopes(const Surface& s, const std::string& name) {
  constexpr double kMaxMedianSlope = 1000;
  if (s.nx < 2) return;
  const std::size_t pairs = (s.nx - 1) * s.ny;
  const std::size_t stride = std::max<std::size_t>(1, pairs / 65536);
  std::vector<double> slope;
  slope.reserve(pairs / stride + 1);
  for (std::size_t k = 0; k < pairs; k += stride) {
    const std::size_t iy = k / (s.nx - 1), ix = k % (s.nx - 1), i = iy * s.nx + ix;
    if (s.valid[i] && s.valid[i + 1]) slope.push_back(std::abs(s.z[i + 1] - s.z[i]) / s.dx);
  }
  if (slope.size() < 16) return;
  auto mid = slope.begin() + slope.size() / 2;
  std::nth_element(slope.begin(), mid, slope.end());
  if (*mid > kMaxMedianSlope) {
    char b[200];
    std::snprintf(b, sizeof b,
                  "heights implausible for the spacing: the median slope between neighbouring "
                  "samples is %.3g (%.4f deg) at a spacing of ",
                  *mid, std::atan(*mid) * 180 / 3.14159265358979323846);
    throw FileError(name, b + detail::format_length_any(s.dx) +
                              ": not a surface; a wrong height unit (--z-scale) or spacing "
                              "(--spacing), or a picture rather than a height map?");
  }
}

}  // namespace

namespace detail {
void check_surface_memory(const std::string& name, std::uint64_t file_bytes, std::uint64_t samples,
                          std::uint64_t extra) {
  const std::uint64_t bytes = mul_sat(samples, sizeof(double) + 1);
  check_expansion(name, file_bytes, bytes > UINT64_MAX - extra ? UINT64_MAX : bytes + extra,
                  "a height map of " + std::to_string(samples) + " samples");
}
}  // namespace detail

std::string format_name(SurfaceFormat format) {
  if (format == SurfaceFormat::Auto) return "auto";
  return info(format).name;
}

bool format_can_write(SurfaceFormat format) { return info(format).can_write; }
bool format_needs_spacing(SurfaceFormat format) { return info(format).needs_spacing; }

SurfaceFormat format_from_extension(const std::string& path) {
  std::string e = lower_extension(path);
  if (e == ".x3p") return SurfaceFormat::X3p;
  if (e == ".dat") return SurfaceFormat::MetroProDat;
  if (e == ".datx") return SurfaceFormat::Datx;
  if (e == ".sur") return SurfaceFormat::Sur;
  if (e == ".plu" || e == ".apx") return SurfaceFormat::Plu;
  if (e == ".gwy") return SurfaceFormat::Gwy;
  if (e == ".xyz") return SurfaceFormat::AsciiXyz;
  if (e == ".txt" || e == ".asc" || e == ".csv") return SurfaceFormat::AsciiGrid;
  if (e == ".npy") return SurfaceFormat::Npy;
  if (e == ".exr") return SurfaceFormat::Exr;
  if (e == ".tif" || e == ".tiff") return SurfaceFormat::Tiff;
  return SurfaceFormat::Auto;
}

SurfaceFormat format_from_magic(std::span<const std::uint8_t> h) {
  auto starts = [&](std::initializer_list<std::uint8_t> m) {
    return h.size() >= m.size() && std::equal(m.begin(), m.end(), h.begin());
  };
  if (starts({'P', 'K', 3, 4})) return SurfaceFormat::X3p;
  if (starts({0x88, 0x1B, 0x03}) && h.size() >= 4 && h[3] >= 0x6F && h[3] <= 0x71)
    return SurfaceFormat::MetroProDat;
  if (starts({0x89, 'H', 'D', 'F', 0x0D, 0x0A, 0x1A, 0x0A})) return SurfaceFormat::Datx;
  if (starts({'D', 'I', 'G', 'I', 'T', 'A', 'L', ' ', 'S', 'U', 'R', 'F'}))
    return SurfaceFormat::Sur;
  if (starts({'G', 'W', 'Y', 'P'})) return SurfaceFormat::Gwy;
  if (starts({0x93, 'N', 'U', 'M', 'P', 'Y'})) return SurfaceFormat::Npy;
  if (starts({0x76, 0x2f, 0x31, 0x01})) return SurfaceFormat::Exr;
  if (starts({'I', 'I', 42, 0}) || starts({'M', 'M', 0, 42})) return SurfaceFormat::Tiff;
  return SurfaceFormat::Auto;
}

namespace {
Surface read_surface_file(const std::string& path, const ReadOptions& options,
                          SurfaceFormat format) {
  auto data = read_file_bytes(path, options.max_file_bytes);
  if (format == SurfaceFormat::Auto) format = format_from_magic(data);
  if (format == SurfaceFormat::Auto) format = format_from_extension(path);
  ReadOptions opt = options;
  double x0 = 0, y0 = 0;
  if (format == SurfaceFormat::Npy) read_npy_sidecar(path, opt, x0, y0);
  if (format != SurfaceFormat::Auto && format_needs_spacing(format) &&
      format != SurfaceFormat::AsciiGrid && (!opt.dx || !opt.dy))
    throw FileError(path, "the " + format_name(format) +
                              " format stores no sample spacing: pass --spacing (e.g. 110nm)" +
                              (format == SurfaceFormat::Npy ? " or add a JSON sidecar" : ""));
  Surface s = read_surface_bytes(data, format, path, opt);
  if (format == SurfaceFormat::Npy) {
    s.x0 = x0;
    s.y0 = y0;
  }
  return s;
}
}  // namespace

Surface read_surface_bytes(std::span<const std::uint8_t> data, SurfaceFormat format,
                           const std::string& name, const ReadOptions& options) {
  if (format == SurfaceFormat::Auto) format = format_from_magic(data);
  if (format == SurfaceFormat::Auto) {
    if (const char* picture = picture_format(data))
      throw FileError(name, std::string("a ") + picture +
                                " picture, not a height map: microbrdf reads heights measured by "
                                "a profilometer (.x3p .datx .sur .plu .dat .gwy) or stored as "
                                "numbers (float TIFF or EXR, .npy, text grids, with --spacing)");
    throw FileError(name,
                    "unrecognised file format (known: .x3p .dat .datx .sur .plu .gwy .xyz "
                    ".txt/.asc/.csv .npy .exr .tif)");
  }
  Surface s;
  switch (format) {
    case SurfaceFormat::X3p:
      s = detail::read_x3p(data, name);
      break;
    case SurfaceFormat::MetroProDat:
      s = detail::read_metropro_dat(data, name);
      break;
    case SurfaceFormat::Datx:
      s = detail::read_datx(data, name);
      break;
    case SurfaceFormat::Sur:
      s = detail::read_sur(data, name);
      break;
    case SurfaceFormat::Plu:
      s = detail::read_plu(data, name);
      break;
    case SurfaceFormat::Gwy:
      s = detail::read_gwy(data, name);
      break;
    case SurfaceFormat::AsciiXyz:
    case SurfaceFormat::AsciiGrid:
      s = detail::read_ascii(data, name, options);
      break;
    case SurfaceFormat::Npy:
      s = detail::read_npy(data, name, options);
      break;
    case SurfaceFormat::Exr:
      s = detail::read_exr(data, name, options);
      break;
    case SurfaceFormat::Tiff:
      s = detail::read_tiff(data, name, options);
      break;
    case SurfaceFormat::Auto:
      break;
  }
  // --z-scale: the unit of formats that store none (the TIFF reader applies it itself).
  if (options.z_scale && format != SurfaceFormat::Tiff) {
    const bool unitless = format == SurfaceFormat::Exr || format == SurfaceFormat::Npy ||
                          format == SurfaceFormat::AsciiGrid || format == SurfaceFormat::AsciiXyz;
    if (!unitless)
      throw FileError(name, format_name(format) +
                                " files store their heights with a unit; --z-scale applies to "
                                "TIFF, EXR, .npy and text grids only");
    for (auto& v : s.z) v *= *options.z_scale;
  }
  // A stored spacing may be overridden (e.g. uncalibrated instruments).
  if (options.dx) s.dx = *options.dx;
  if (options.dy) s.dy = *options.dy;
  if (!(s.dx > 0) || !(s.dy > 0) || !std::isfinite(s.dx) || !std::isfinite(s.dy))
    throw FileError(name, "spacing is missing, zero or not finite; pass --spacing");
  if (s.dx > kMaxSpacing || s.dy > kMaxSpacing)
    throw FileError(name, "spacing " + std::to_string(s.dx) + " x " + std::to_string(s.dy) +
                              " m is absurd (over 1 m); wrong unit? pass --spacing");
  if (s.dx < kMinSpacing || s.dy < kMinSpacing)
    throw FileError(name, "spacing " + detail::format_length_any(s.dx) + " x " +
                              detail::format_length_any(s.dy) +
                              " is absurd (below 1 pm); wrong unit? pass --spacing");
  s.sync_mask();
  if (s.valid_count() == 0) throw FileError(name, "contains no valid height sample");
  check_heights(s, name);
  check_plausible_slopes(s, name);
  if (s.meta.source_path.empty()) s.meta.source_path = name;
  if (s.meta.format.empty()) s.meta.format = format_name(format);
  return s;
}

Surface read_surface(const std::string& path, const ReadOptions& options, SurfaceFormat format) {
  try {
    return read_surface_file(path, options, format);
  } catch (const std::bad_alloc&) {
    throw FileError(path, "out of memory while reading (memory budget " +
                              format_bytes(memory_budget()) + "; --max-memory)");
  }
}

void write_surface(const Surface& s, const std::string& path, SurfaceFormat format) {
  if (format == SurfaceFormat::Auto) format = format_from_extension(path);
  if (format == SurfaceFormat::Auto)
    throw FileError(path,
                    "cannot tell the output format from the extension (use .x3p .gwy .xyz "
                    ".txt .npy)");
  if (!format_can_write(format))
    throw FileError(path, "writing " + format_name(format) +
                              " is not supported (writable: x3p gwy xyz txt npy)");
  s.check();
  AtomicFile out(path);
  try {
    switch (format) {
      case SurfaceFormat::X3p:
        detail::write_x3p(s, out.temp_path());
        break;
      case SurfaceFormat::Gwy:
        detail::write_gwy(s, out.temp_path());
        break;
      case SurfaceFormat::AsciiXyz:
        detail::write_ascii_xyz(s, out.temp_path());
        break;
      case SurfaceFormat::AsciiGrid:
        detail::write_ascii_grid(s, out.temp_path());
        break;
      case SurfaceFormat::Npy:
        detail::write_npy(s, out.temp_path());
        break;
      default:
        throw FileError(path, "writing this format is not supported");
    }
  } catch (const FileError& e) {
    throw FileError(path, e.problem());  // name the user's path, not the temporary
  }
  if (format == SurfaceFormat::Npy) write_npy_sidecar(s, path);
  out.commit();
}

}  // namespace microbrdf
