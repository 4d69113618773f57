// Digital Surf .sur reader (binary, PC byte order).
//
// Layout (docs/formats.md §5): a fixed 512-byte little-endian header, then
// comment_size bytes of comment, private_size bytes of private zone, then xres*yres points of
// int16 or int32 (point size 16/32), row-major with x fastest. Heights: z = raw*dz + z offset,
// in the dz unit. Rows are kept in file order.
//
// Non-measured points: when the header's special_points field is non-zero, points whose raw
// value equals zmin - 2 are invalid (observed: sur-2.sur has special_points = 1 and 117 such
// points). With special_points = 0 every point is taken as measured.
//
// Not supported (clear errors): Macintosh byte order (format 257), compressed files
// ("DSCOMPRESSED"), object types other than profile (1) and surface (2). Of a multi-object
// file only the first object is read (noted in the metadata).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <sstream>
#include <string>

#include "core/byte_reader.hpp"
#include "microbrdf/error.hpp"
#include "surface/formats.hpp"

namespace microbrdf::detail {
namespace {

constexpr std::size_t kHeader = 512;

// Printable ASCII kept, Latin-1 micro sign (0xB5) and UTF-8 micro/mu turned into "u".
std::string clean_text(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    unsigned char c = static_cast<unsigned char>(s[i]);
    if (c >= 0x20 && c < 0x7F) {
      out += static_cast<char>(c);
    } else if (c == 0xB5) {
      out += 'u';
    } else if ((c == 0xC2 || c == 0xCE) && i + 1 < s.size() &&
               (static_cast<unsigned char>(s[i + 1]) == 0xB5 ||
                static_cast<unsigned char>(s[i + 1]) == 0xBC)) {
      out += 'u';
      ++i;
    } else {
      out += '?';
    }
  }
  std::size_t a = out.find_first_not_of(' ');
  if (a == std::string::npos) return "";
  return out.substr(a, out.find_last_not_of(' ') - a + 1);
}

// Metres per unit for a length unit name (after clean_text); 0 when unknown.
double unit_factor(const std::string& u) {
  if (u == "m") return 1;
  if (u == "dm") return 1e-1;
  if (u == "cm") return 1e-2;
  if (u == "mm") return 1e-3;
  if (u == "um") return 1e-6;
  if (u == "nm") return 1e-9;
  if (u == "pm") return 1e-12;
  if (u == "A" || u == "?") return 1e-10;  // Angstrom (Latin-1 0xC5 becomes '?')
  return 0;
}

std::string num(double v) {
  std::ostringstream o;
  o.precision(9);
  o << v;
  return o.str();
}

const char* acquisition_name(unsigned t) {
  switch (t) {
    case 1:
      return "contact stylus";
    case 2:
      return "scanning optical gauge";
    case 3:
      return "thermocouple";
    case 5:
      return "contact stylus with skid";
    case 6:
      return "AFM";
    case 7:
      return "STM";
    case 8:
      return "video";
    case 9:
      return "interferometer";
    case 10:
      return "structured light projection";
    default:
      return nullptr;
  }
}

}  // namespace

Surface read_sur(Bytes data, const std::string& name) {
  ByteReader r(data, name);
  if (r.size() >= 12 &&
      std::string(reinterpret_cast<const char*>(data.data()), 12) == "DSCOMPRESSED")
    r.fail("compressed Digital Surf files (DSCOMPRESSED) are not supported");
  if (r.size() < 12 ||
      std::string(reinterpret_cast<const char*>(data.data()), 12) != "DIGITAL SURF")
    r.fail("not a Digital Surf .sur file (\"DIGITAL SURF\" signature missing)");
  r.require(0, kHeader, "the 512-byte .sur header");

  const unsigned fmt = r.le<std::uint16_t>(12, "format");
  if (fmt == 257)
    r.fail(
        "Macintosh (big-endian) .sur files (format 257) are not supported; re-export with PC "
        "byte order");
  if (fmt != 0) r.fail("unknown .sur format code " + std::to_string(fmt) + " (expected 0 = PC)");

  const unsigned n_objects = r.le<std::uint16_t>(14, "object count");
  const unsigned version = r.le<std::uint16_t>(16, "version");
  const unsigned obj_type = r.le<std::uint16_t>(18, "object type");
  if (obj_type != 1 && obj_type != 2)
    r.fail("object type " + std::to_string(obj_type) +
           " is not supported (only 1 = profile and 2 = surface)");
  const unsigned acquisition = r.le<std::uint16_t>(82);
  const unsigned special_points = r.le<std::uint16_t>(86);
  const unsigned point_bits = r.le<std::uint16_t>(98, "point size");
  if (point_bits != 16 && point_bits != 32)
    r.fail("point size " + std::to_string(point_bits) + " bits is not supported (16 or 32)");
  const std::int64_t zmin = r.le<std::int32_t>(100, "zmin");
  const std::int64_t zmax = r.le<std::int32_t>(104, "zmax");
  const std::int32_t xres = r.le<std::int32_t>(108, "xres");
  const std::int32_t yres = r.le<std::int32_t>(112, "yres");
  const std::uint32_t total_points = r.le<std::uint32_t>(116, "total points");
  if (xres <= 0 || yres <= 0)
    r.fail("corrupt header: grid " + std::to_string(xres) + " x " + std::to_string(yres));
  const double dx_raw = r.le<float>(120, "dx");
  const double dy_raw = r.le<float>(124, "dy");
  const double dz_raw = r.le<float>(128, "dz");

  const std::string dx_unit = clean_text(r.text(180, 16));
  const std::string dy_unit = clean_text(r.text(196, 16));
  const std::string dz_unit = clean_text(r.text(212, 16));
  const std::string x_len_unit = clean_text(r.text(228, 16));
  const std::string y_len_unit = clean_text(r.text(244, 16));
  const std::string z_len_unit = clean_text(r.text(260, 16));
  auto factor = [&](const std::string& step_unit, const std::string& len_unit, const char* axis) {
    const std::string& u = step_unit.empty() ? len_unit : step_unit;
    double f = unit_factor(u);
    if (f == 0)
      r.fail(std::string("unsupported ") + axis + " unit '" + u + "' (expected a length unit)");
    return f;
  };
  const double fz = factor(dz_unit, z_len_unit, "z");
  const double fx = factor(dx_unit, x_len_unit, "x");
  const double fy = obj_type == 1 && dy_unit.empty() && y_len_unit.empty()
                        ? fx
                        : factor(dy_unit, y_len_unit, "y");

  if (!std::isfinite(dz_raw) || dz_raw == 0)
    r.fail("corrupt header: z step dz = " + num(dz_raw) + " is zero or invalid");
  if (!std::isfinite(dx_raw) || dx_raw < 0 || !std::isfinite(dy_raw) || dy_raw < 0)
    r.fail("corrupt header: lateral steps dx = " + num(dx_raw) + ", dy = " + num(dy_raw) +
           " are negative or invalid");

  const unsigned comment_size = r.le<std::uint16_t>(334);
  const unsigned private_size = r.le<std::uint16_t>(336);
  const std::uint64_t data_offset = kHeader + comment_size + private_size;
  if (data_offset > r.size())
    r.fail("truncated: comment (" + std::to_string(comment_size) + " bytes) and private zone (" +
           std::to_string(private_size) + " bytes) run past the end of the file");
  const std::uint64_t bytes_per_point = point_bits / 8;
  const std::uint64_t available = r.size() - data_offset;
  const std::uint64_t nx = static_cast<std::uint64_t>(xres), ny = static_cast<std::uint64_t>(yres);
  check_grid(r, nx, ny, 0, available);
  if (nx * ny * bytes_per_point > available)
    r.fail("truncated: header says " + std::to_string(nx) + " x " + std::to_string(ny) + " int" +
           std::to_string(point_bits) + " points (" + std::to_string(nx * ny * bytes_per_point) +
           " bytes) but only " + std::to_string(available) + " bytes follow");

  const double x_off = r.le<float>(466), y_off = r.le<float>(470), z_off = r.le<float>(474);
  const double z_offset = std::isfinite(z_off) ? z_off : 0.0;

  Surface s;
  s.nx = nx;
  s.ny = ny;
  s.dx = dx_raw * fx;
  s.dy = dy_raw * fy;
  if (obj_type == 1 && ny == 1 && !(s.dy > 0)) s.dy = s.dx;  // a profile has no y step
  if (std::isfinite(x_off)) s.x0 = x_off * fx;
  if (std::isfinite(y_off)) s.y0 = y_off * fy;
  const std::size_t n = nx * ny;
  s.z.assign(n, 0.0);
  s.valid.assign(n, 1);
  const std::int64_t marker = zmin - 2;
  std::size_t n_marked = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::int64_t raw =
        point_bits == 16 ? std::int64_t{r.le<std::int16_t>(data_offset + 2 * i, "point data")}
                         : std::int64_t{r.le<std::int32_t>(data_offset + 4 * i, "point data")};
    if (special_points != 0 && raw == marker) {
      s.z[i] = std::numeric_limits<double>::quiet_NaN();
      ++n_marked;
    } else {
      s.z[i] = (static_cast<double>(raw) * dz_raw + z_offset) * fz;
    }
  }

  auto& m = s.meta;
  m.format = "sur";
  if (const char* a = acquisition_name(acquisition)) m.instrument = a;
  const unsigned sec = r.le<std::uint16_t>(306), min = r.le<std::uint16_t>(308),
                 hour = r.le<std::uint16_t>(310), day = r.le<std::uint16_t>(312),
                 month = r.le<std::uint16_t>(314), year = r.le<std::uint16_t>(316);
  if (year != 0 && month >= 1 && month <= 12 && day >= 1 && day <= 31 && hour < 24 && min < 60 &&
      sec < 61) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%04u-%02u-%02uT%02u:%02u:%02u", year, month, day, hour, min,
                  sec);
    m.date = buf;
  }
  if (comment_size > 0) m.comment = clean_text(r.text(kHeader, comment_size, "comment"));
  m.z_unit_in_file = dz_unit.empty() ? z_len_unit : dz_unit;
  m.set("sur_version", std::to_string(version));
  m.set("object_type", obj_type == 1 ? "profile" : "surface");
  const std::string object_name = clean_text(r.text(20, 30));
  if (!object_name.empty()) m.set("object_name", object_name);
  const std::string operator_name = clean_text(r.text(50, 30));
  if (!operator_name.empty()) m.set("operator", operator_name);
  m.set("acquisition_type", std::to_string(acquisition));
  m.set("point_size_bits", std::to_string(point_bits));
  m.set("z_step", num(dz_raw) + " " + m.z_unit_in_file);
  m.set("zmin_zmax_raw", std::to_string(zmin) + "," + std::to_string(zmax));
  m.set("special_points", std::to_string(special_points));
  if (special_points != 0) {
    m.set("non_measured_marker_raw", std::to_string(marker));
    m.set("non_measured_points", std::to_string(n_marked));
  }
  const unsigned inversion = r.le<std::uint16_t>(290);
  if (inversion != 0)
    m.set("inversion_flag", std::to_string(inversion) + " (recorded, not applied)");
  if (total_points != nx * ny)
    m.set("total_points_field", std::to_string(total_points) + " (differs from xres*yres)");
  const double rx = r.le<float>(276), ry = r.le<float>(280), rz = r.le<float>(284);
  if (rx != 1 || ry != 1 || rz != 1)
    m.set("unit_ratios", num(rx) + "," + num(ry) + "," + num(rz) + " (not applied)");
  if (n_objects > 1) {
    m.set("objects_in_file", std::to_string(n_objects));
    m.set("note", "only the first of " + std::to_string(n_objects) + " objects was read");
  }
  return s;
}

}  // namespace microbrdf::detail
