// Format dispatch: extension / magic detection, file loading with a size cap, npy sidecars,
// atomic writes.
#include "microbrdf/io.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
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
  nlohmann::json j;
  try {
    std::ifstream in(side);
    j = nlohmann::json::parse(in);
  } catch (const std::exception& e) {
    throw FileError(side.string(), std::string("invalid JSON sidecar: ") + e.what());
  }
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

}  // namespace

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

std::vector<std::uint8_t> read_file_bytes(const std::string& path, std::uint64_t max_bytes) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw FileError(path, "no such file");
  if (fs::is_directory(path, ec)) throw FileError(path, "is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(path, std::string("cannot open: ") + std::strerror(errno));
  in.seekg(0, std::ios::end);
  std::streamoff n = in.tellg();
  if (n < 0) throw FileError(path, "cannot determine file size");
  if (static_cast<std::uint64_t>(n) > max_bytes)
    throw FileError(path, "file is " + std::to_string(n) + " bytes, over the limit of " +
                              std::to_string(max_bytes));
  in.seekg(0);
  std::vector<std::uint8_t> data(static_cast<std::size_t>(n));
  in.read(reinterpret_cast<char*>(data.data()), n);
  if (!in) throw FileError(path, "read error");
  return data;
}

Surface read_surface_bytes(std::span<const std::uint8_t> data, SurfaceFormat format,
                           const std::string& name, const ReadOptions& options) {
  if (format == SurfaceFormat::Auto) format = format_from_magic(data);
  if (format == SurfaceFormat::Auto) {
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
  // A stored spacing may be overridden (e.g. uncalibrated instruments).
  if (options.dx) s.dx = *options.dx;
  if (options.dy) s.dy = *options.dy;
  if (!(s.dx > 0) || !(s.dy > 0) || !std::isfinite(s.dx) || !std::isfinite(s.dy))
    throw FileError(name, "spacing is missing, zero or not finite; pass --spacing");
  s.sync_mask();
  if (s.valid_count() == 0) throw FileError(name, "contains no valid height sample");
  if (s.meta.source_path.empty()) s.meta.source_path = name;
  if (s.meta.format.empty()) s.meta.format = format_name(format);
  return s;
}

Surface read_surface(const std::string& path, const ReadOptions& options, SurfaceFormat format) {
  auto data = read_file_bytes(path, options.max_file_bytes);
  if (format == SurfaceFormat::Auto) format = format_from_magic(data);
  if (format == SurfaceFormat::Auto) format = format_from_extension(path);
  ReadOptions opt = options;
  double x0 = 0, y0 = 0;
  if (format == SurfaceFormat::Npy) read_npy_sidecar(path, opt, x0, y0);
  if (format_needs_spacing(format) && format != SurfaceFormat::AsciiGrid && (!opt.dx || !opt.dy))
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
