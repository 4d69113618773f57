// Zygo MetroPro binary .dat reader (header formats 1, 2 and 3).
//
// Layout (docs/formats.md §2): a big-endian header of `header_size` bytes
// (834 for formats 1/2, 4096 for format 3), then n_buckets intensity frames of w*h uint16 BE
// (skipped), then the phase block of w*h int32 BE, row-major, x fastest. Phase values
// >= 2147483640 are invalid. height [m] = raw * scale_factor * obliquity * wavelength / R with
// R = 4096, 32768 or 131072 for phase_res 0, 1, 2; negated when the sign flag is set.
// Rows are kept in file order (row 0 = first stored row).
#include <cmath>
#include <cstdint>
#include <ctime>
#include <limits>
#include <sstream>
#include <string>

#include "core/byte_reader.hpp"
#include "microbrdf/error.hpp"
#include "surface/formats.hpp"

namespace microbrdf::detail {
namespace {

constexpr std::int32_t kInvalidPhase = 2147483640;
constexpr std::uint32_t kMinHeader = 570;

// Header text may hold anything; keep printable ASCII only so metadata stays valid UTF-8.
std::string clean_text(std::string s) {
  std::string out;
  for (unsigned char c : s) out += (c >= 0x20 && c < 0x7F) ? static_cast<char>(c) : '?';
  std::size_t a = out.find_first_not_of(' ');
  if (a == std::string::npos) return "";
  return out.substr(a, out.find_last_not_of(' ') - a + 1);
}

std::string iso_utc(std::int32_t t) {
  std::time_t tt = static_cast<std::time_t>(t);
  std::tm tm{};
  if (gmtime_r(&tt, &tm) == nullptr) return "";
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

std::string num(double v) {
  std::ostringstream o;
  o.precision(9);
  o << v;
  return o.str();
}

}  // namespace

Surface read_metropro_dat(Bytes data, const std::string& name) {
  ByteReader r(data, name);
  if (r.size() < 4 || data[0] != 0x88 || data[1] != 0x1B || data[2] != 0x03 || data[3] < 0x6F ||
      data[3] > 0x71)
    r.fail("not a Zygo MetroPro .dat file (magic 88 1B 03 6F/70/71 missing)");
  const int header_format = data[3] - 0x6F + 1;

  const std::uint32_t header_size = r.be<std::uint32_t>(6, "header size");
  if (header_size < kMinHeader)
    r.fail("corrupt header: header size " + std::to_string(header_size) +
           " is below the minimum of " + std::to_string(kMinHeader) + " bytes");
  if (header_size > r.size())
    r.fail("truncated: header size is " + std::to_string(header_size) + " bytes but the file has " +
           std::to_string(r.size()) + " bytes");

  const std::uint64_t iw = r.be<std::uint16_t>(52, "intensity width");
  const std::uint64_t ih = r.be<std::uint16_t>(54, "intensity height");
  const std::uint64_t nbuckets = r.be<std::uint16_t>(56, "intensity bucket count");
  const std::uint64_t pw = r.be<std::uint16_t>(68, "phase width");
  const std::uint64_t ph = r.be<std::uint16_t>(70, "phase height");
  const std::int32_t timestamp = r.be<std::int32_t>(76, "time stamp");
  const double scale = r.be<float>(164, "interferometric scale factor");
  const double wavelength = r.be<float>(168, "wavelength");
  const double na = r.be<float>(172, "numerical aperture");
  const double obliquity = r.be<float>(176, "obliquity factor");
  const double magnification = r.be<float>(180, "magnification");
  const double lateral = r.be<float>(184, "lateral resolution");
  const std::int16_t phase_res = r.be<std::int16_t>(218, "phase resolution");
  const std::int16_t sign = r.be<std::int16_t>(232, "data sign flag");

  if (pw == 0 || ph == 0)
    r.fail("no phase data: phase size is " + std::to_string(pw) + " x " + std::to_string(ph));

  // Intensity frames come first; skip them.
  const std::uint64_t intensity_bytes = iw * ih * 2 * nbuckets;  // < 2^50, no overflow
  const std::uint64_t after_header = r.size() - header_size;
  if (intensity_bytes > after_header)
    r.fail("truncated: header says " + std::to_string(nbuckets) + " intensity frame(s) of " +
           std::to_string(iw) + " x " + std::to_string(ih) + " uint16 (" +
           std::to_string(intensity_bytes) + " bytes) but only " + std::to_string(after_header) +
           " bytes follow the header");
  const std::uint64_t phase_offset = header_size + intensity_bytes;
  const std::uint64_t available = r.size() - phase_offset;
  if (pw * ph * 4 > available)
    r.fail("truncated: header says " + std::to_string(pw) + " x " + std::to_string(ph) +
           " int32 phase samples (" + std::to_string(pw * ph * 4) + " bytes) but only " +
           std::to_string(available) + " bytes follow");
  check_grid(r, pw, ph, 4, available);

  double R = 0;
  switch (phase_res) {
    case 0:
      R = 4096;
      break;
    case 1:
      R = 32768;
      break;
    case 2:
      R = 131072;
      break;
    default:
      r.fail("unsupported phase resolution code " + std::to_string(phase_res) +
             " at offset 218 (expected 0, 1 or 2)");
  }
  if (!std::isfinite(wavelength) || !(wavelength > 0))
    r.fail("corrupt header: wavelength " + num(wavelength) + " m is not a positive number");
  if (!std::isfinite(scale) || scale == 0)
    r.fail("corrupt header: interferometric scale factor " + num(scale) + " is zero or invalid");
  if (!std::isfinite(obliquity) || obliquity == 0)
    r.fail("corrupt header: obliquity factor " + num(obliquity) + " is zero or invalid");
  if (!std::isfinite(lateral) || lateral < 0)
    r.fail("corrupt header: lateral resolution " + num(lateral) + " m is negative or invalid");

  double k = scale * obliquity * wavelength / R;
  if (sign != 0) k = -k;

  Surface s;
  s.nx = pw;
  s.ny = ph;
  s.dx = s.dy = lateral;
  s.z.assign(pw * ph, 0.0);
  s.valid.assign(pw * ph, 1);
  const std::size_t n = pw * ph;
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t raw = r.be<std::int32_t>(phase_offset + 4 * i, "phase data");
    s.z[i] = raw >= kInvalidPhase ? std::numeric_limits<double>::quiet_NaN() : raw * k;
  }

  auto& m = s.meta;
  m.format = "dat";
  const int vmaj = r.be<std::int16_t>(42), vmin = r.be<std::int16_t>(44),
            vbug = r.be<std::int16_t>(46);
  const int system_type = r.be<std::int16_t>(238);
  m.instrument = "Zygo (MetroPro " + std::to_string(vmaj) + "." + std::to_string(vmin) + "." +
                 std::to_string(vbug) + ", system type " + std::to_string(system_type) + ")";
  if (timestamp > 0) m.date = iso_utc(timestamp);
  m.comment = clean_text(r.text(80, 82, "comment"));
  m.z_unit_in_file = "phase counts (" + std::to_string(static_cast<long>(R)) + " per wave)";
  m.set("header_format", std::to_string(header_format));
  m.set("software_date", clean_text(r.text(12, 30, "software date")));
  m.set("wavelength_m", num(wavelength));
  m.set("interferometric_scale_factor", num(scale));
  m.set("obliquity_factor", num(obliquity));
  if (na != 0 && std::isfinite(na)) m.set("numerical_aperture", num(na));
  if (magnification != 0 && std::isfinite(magnification))
    m.set("magnification", num(magnification));
  m.set("phase_resolution_counts_per_wave", std::to_string(static_cast<long>(R)));
  m.set("height_per_count_m", num(std::fabs(k)));
  if (sign != 0) m.set("data_inverted", "true");
  m.set("system_type", std::to_string(system_type));
  const std::string objective = clean_text(r.text(246, 12, "objective name"));
  if (!objective.empty()) m.set("objective", objective);
  const std::string part = clean_text(r.text(258, 40, "part name"));
  if (!part.empty()) m.set("part_name", part);
  const std::string serial = clean_text(r.text(320, 40, "part serial number"));
  if (!serial.empty()) m.set("part_serial", serial);
  m.set("phase_origin_px",
        std::to_string(r.be<std::int16_t>(64)) + "," + std::to_string(r.be<std::int16_t>(66)));
  m.set("camera_size_px",
        std::to_string(r.be<std::int16_t>(234)) + "x" + std::to_string(r.be<std::int16_t>(236)));
  m.set("intensity_frames", std::to_string(nbuckets));
  if (lateral == 0) m.set("uncalibrated_lateral", "true");
  return s;
}

}  // namespace microbrdf::detail
