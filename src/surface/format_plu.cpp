// Sensofar .plu reader (topography measurements).
//
// Layout (docs/formats.md §6), little-endian, no magic:
//     0  char[128]  date string ("Fri Mar 10 16:35:59 2023")
//   128  u32        time (Unix seconds)
//   132  char[256]  comment
//   388  calibration: u32 yres, xres, N_tall; f32 dy_multip, um/pixel x, um/pixel y, x0, y0,
//                     um/pixel tall, z0                                          (40 bytes)
//   428  configuration: u32 type (3 = topography), algorithm, method, objective, area type
//   448  scan settings, 40 bytes: for area type 6 (coordinates) the point-scan settings, else
//        u32 xres_area, yres_area, xres, yres, na; f64 incr_z; f32 range; u32 n_planes,
//        threshold (both variants are 40 bytes long)
//   488  u8 restore, num_layers, version, hardware config, num_images; 3 reserved; u32 factor
//   500  first layer: u32 yres, u32 xres, yres*xres f32 heights in um (row-major), f32 min, max
// Undefined points hold 1000001. Only the first layer is read. Rows are kept in file order.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <limits>
#include <sstream>
#include <string>

#include "core/byte_reader.hpp"
#include "microbrdf/error.hpp"
#include "surface/formats.hpp"

namespace microbrdf::detail {
namespace {

constexpr std::size_t kCalibration = 388;
constexpr std::size_t kConfig = 428;
constexpr std::size_t kScan = 448;
constexpr std::size_t kConfig2 = 488;
constexpr std::size_t kFirstLayer = 500;
constexpr float kUndefined = 1000001.0f;
constexpr std::uint32_t kTypeTopography = 3;
constexpr std::uint32_t kAreaCoordinates = 6;

std::string clean_text(const std::string& s) {
  std::string out;
  for (unsigned char c : s) out += (c >= 0x20 && c < 0x7F) ? static_cast<char>(c) : '?';
  std::size_t a = out.find_first_not_of(' ');
  if (a == std::string::npos) return "";
  return out.substr(a, out.find_last_not_of(' ') - a + 1);
}

std::string num(double v) {
  std::ostringstream o;
  o.precision(9);
  o << v;
  return o.str();
}

// "Fri Mar 10 16:35:59 2023" -> "2023-03-10T16:35:59" (local instrument time); "" if unparsable.
std::string iso_date(const std::string& s) {
  std::tm tm{};
  const char* end = strptime(s.c_str(), "%a %b %d %H:%M:%S %Y", &tm);
  if (end == nullptr) return "";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%04d-%02d-%02dT%02d:%02d:%02d", tm.tm_year + 1900, tm.tm_mon + 1,
                tm.tm_mday, tm.tm_hour, tm.tm_min, tm.tm_sec);
  return buf;
}

const char* type_name(std::uint32_t t) {
  switch (t) {
    case 0:
      return "image";
    case 1:
      return "profile";
    case 2:
      return "multi-profile";
    case 3:
      return "topography";
    case 4:
      return "coordinates";
    case 5:
      return "thickness";
    default:
      return "unknown";
  }
}

}  // namespace

Surface read_plu(Bytes data, const std::string& name) {
  ByteReader r(data, name);
  if (r.size() < kFirstLayer + 8)
    r.fail("truncated or not a Sensofar .plu file: " + std::to_string(r.size()) +
           " bytes, the header alone is " + std::to_string(kFirstLayer + 8) + " bytes");

  const std::uint32_t cal_yres = r.le<std::uint32_t>(kCalibration);
  const std::uint32_t cal_xres = r.le<std::uint32_t>(kCalibration + 4);
  const double um_px_x = r.le<float>(kCalibration + 16, "um per pixel x");
  const double um_px_y = r.le<float>(kCalibration + 20, "um per pixel y");
  const double off_x = r.le<float>(kCalibration + 24);
  const double off_y = r.le<float>(kCalibration + 28);
  const double off_z = r.le<float>(kCalibration + 36);

  const std::uint32_t type = r.le<std::uint32_t>(kConfig, "measurement type");
  const std::uint32_t algorithm = r.le<std::uint32_t>(kConfig + 4);
  const std::uint32_t method = r.le<std::uint32_t>(kConfig + 8);
  const std::uint32_t objective = r.le<std::uint32_t>(kConfig + 12);
  const std::uint32_t area_type = r.le<std::uint32_t>(kConfig + 16);
  const unsigned num_layers = data[kConfig2 + 1];
  const unsigned version = data[kConfig2 + 2];

  if (type != kTypeTopography)
    r.fail("measurement type " + std::to_string(type) + " (" + type_name(type) +
           ") is not supported; only topography (3) is (or this is not a .plu file)");
  if (num_layers == 0) r.fail("the file holds no data layer (num_layers = 0)");
  if (!std::isfinite(um_px_x) || um_px_x < 0 || !std::isfinite(um_px_y) || um_px_y < 0)
    r.fail("corrupt calibration: pixel size " + num(um_px_x) + " x " + num(um_px_y) +
           " um is negative or invalid");

  const std::uint64_t ny = r.le<std::uint32_t>(kFirstLayer, "layer rows");
  const std::uint64_t nx = r.le<std::uint32_t>(kFirstLayer + 4, "layer columns");
  const std::uint64_t data_offset = kFirstLayer + 8;
  const std::uint64_t available = r.size() - data_offset;
  check_grid(r, nx, ny, 0, available);
  if (nx * ny * 4 > available)
    r.fail("truncated: layer header says " + std::to_string(nx) + " x " + std::to_string(ny) +
           " float32 heights (" + std::to_string(nx * ny * 4) + " bytes) but only " +
           std::to_string(available) + " bytes follow");

  Surface s;
  s.nx = nx;
  s.ny = ny;
  s.dx = um_px_x * 1e-6;
  s.dy = um_px_y * 1e-6;
  const std::size_t n = nx * ny;
  s.z.assign(n, 0.0);
  s.valid.assign(n, 1);
  std::size_t undefined = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const float v = r.le<float>(data_offset + 4 * i, "height data");
    if (v == kUndefined) {
      s.z[i] = std::numeric_limits<double>::quiet_NaN();
      ++undefined;
    } else {
      s.z[i] = static_cast<double>(v) * 1e-6;  // non-finite values stay non-finite
    }
  }

  auto& m = s.meta;
  m.format = "plu";
  m.instrument = "Sensofar";
  const std::string date = clean_text(r.text(0, 128, "date"));
  m.date = iso_date(date);
  if (m.date.empty()) m.date = date;
  m.comment = clean_text(r.text(132, 256, "comment"));
  if (m.comment == "(None)") m.comment.clear();
  m.z_unit_in_file = "um";
  m.set("date_string", date);
  m.set("time_unix", std::to_string(r.le<std::uint32_t>(128)));
  m.set("plu_version", std::to_string(version));
  m.set("measurement_type", std::to_string(type) + " (" + type_name(type) + ")");
  m.set("algorithm", std::to_string(algorithm));
  m.set("method", std::to_string(method));
  m.set("objective_index", std::to_string(objective));
  m.set("area_type", std::to_string(area_type));
  m.set("um_per_pixel", num(um_px_x) + " x " + num(um_px_y));
  if (std::isfinite(off_x) && std::isfinite(off_y) && std::isfinite(off_z))
    m.set("stage_offset_um", num(off_x) + "," + num(off_y) + "," + num(off_z));
  if (area_type != kAreaCoordinates) {
    const double incr_z = r.le<double>(kScan + 20);
    const std::uint32_t n_planes = r.le<std::uint32_t>(kScan + 32);
    m.set("z_planes", std::to_string(n_planes));
    if (std::isfinite(incr_z)) m.set("z_increment", num(incr_z));
  }
  m.set("layers_in_file", std::to_string(num_layers));
  if (num_layers > 1) m.set("note", "only the first of the layers was read");
  if (cal_xres != nx || cal_yres != ny)
    m.set("calibration_grid", std::to_string(cal_xres) + " x " + std::to_string(cal_yres) +
                                  " (differs from the layer grid)");
  m.set("undefined_points", std::to_string(undefined));
  return s;
}

}  // namespace microbrdf::detail
