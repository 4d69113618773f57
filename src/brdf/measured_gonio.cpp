// Gonioreflectometer point sets as CSV (include/microbrdf/measured.hpp; docs/measured.md).
#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>

#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/io.hpp"
#include "microbrdf/measured.hpp"
#include "microbrdf/memory_budget.hpp"

namespace microbrdf {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;
const char* const kColumns[6] = {"theta_i_deg", "phi_i_deg",     "theta_o_deg",
                                 "phi_o_deg",   "wavelength_nm", "brdf_per_sr"};
constexpr const char* kSigmaColumn = "brdf_sigma_per_sr";

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    out.push_back(
        trim(line.substr(start, comma == std::string_view::npos ? comma : comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return out;
}

Vec3 direction(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

}  // namespace

Vec3 GonioPoint::wi() const { return direction(theta_i, phi_i); }
Vec3 GonioPoint::wo() const { return direction(theta_o, phi_o); }

// What one data row costs in memory: its GonioPoint here and, in effective_ndf, a working copy
// (three directions and a value, 80 bytes, in a vector that may double) and an 8-byte index.
constexpr std::uint64_t kBytesPerRow = sizeof(GonioPoint) + 2 * 80 + 8;

GonioData parse_gonio_csv(std::string_view text, const std::string& name) {
  GonioData d;
  // Estimated before any point is stored: a row per line at most.
  const auto rows = static_cast<std::uint64_t>(std::count(text.begin(), text.end(), '\n')) + 1;
  check_memory(name, text.size() + mul_sat(rows, kBytesPerRow),
               "up to " + std::to_string(rows) + " goniometer rows (the text and the points)");
  d.points.reserve(static_cast<std::size_t>(rows));
  int col[6];
  int sigma_col = -1;
  std::size_t ncols = 0;
  bool have_header = false;
  std::size_t pos = 0, line_no = 0;
  auto fail = [&](const std::string& what) {
    throw FileError(name, "line " + std::to_string(line_no) + ": " + what);
  };
  if (text.substr(0, 3) == "\xEF\xBB\xBF") pos = 3;  // a UTF-8 byte-order mark (spreadsheets)
  while (pos < text.size()) {
    const std::size_t nl = text.find('\n', pos);
    const std::string_view line =
        trim(text.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos));
    pos = nl == std::string_view::npos ? text.size() : nl + 1;
    ++line_no;
    if (line.empty() || line.front() == '#') continue;
    const auto cells = split(line);
    if (!have_header) {
      for (int c = 0; c < 6; ++c) {
        col[c] = -1;
        for (std::size_t k = 0; k < cells.size(); ++k)
          if (cells[k] == kColumns[c]) col[c] = static_cast<int>(k);
        if (col[c] < 0)
          fail(std::string("the header has no column \"") + kColumns[c] +
               "\" (needs theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,wavelength_nm,brdf_per_sr)");
      }
      for (std::size_t k = 0; k < cells.size(); ++k)
        if (cells[k] == kSigmaColumn) sigma_col = static_cast<int>(k);
      d.has_sigma = sigma_col >= 0;
      ncols = cells.size();
      have_header = true;
      continue;
    }
    if (cells.size() < ncols)
      fail(std::to_string(cells.size()) + " columns, the header has " + std::to_string(ncols));
    double v[7];
    for (int c = 0; c < 7; ++c) {
      const int k = c < 6 ? col[c] : sigma_col;
      if (k < 0) {
        v[c] = std::numeric_limits<double>::quiet_NaN();
        continue;
      }
      const std::string_view s = cells[static_cast<std::size_t>(k)];
      const auto r = std::from_chars(s.data(), s.data() + s.size(), v[c]);
      if (r.ec != std::errc() || r.ptr != s.data() + s.size() || !std::isfinite(v[c]))
        fail("column \"" + std::string(c < 6 ? kColumns[c] : kSigmaColumn) +
             "\" is not a finite number: \"" + std::string(s) + "\"");
    }
    if (v[0] < 0 || v[0] > 90 || v[2] < 0 || v[2] > 90)
      fail(
          fmt::format("polar angles must lie in [0, 90] deg (theta_i {}, theta_o {})", v[0], v[2]));
    if (!(v[4] > 0) || v[4] > 1e6) fail(fmt::format("wavelength {} nm is not positive", v[4]));
    if (sigma_col >= 0 && v[6] < 0) fail(fmt::format("negative brdf_sigma_per_sr {}", v[6]));
    if (v[5] < 0)
      fail(
          fmt::format("brdf_per_sr is negative ({}): a BRDF cannot be negative (a background "
                      "subtracted too far? clip the file's values at 0)",
                      v[5]));
    GonioPoint p;
    p.theta_i = v[0] * kDeg;
    p.phi_i = v[1] * kDeg;
    p.theta_o = v[2] * kDeg;
    p.phi_o = v[3] * kDeg;
    p.wavelength_m = v[4] * 1e-9;
    p.brdf = v[5];
    p.sigma = v[6];
    d.points.push_back(p);
  }
  if (!have_header) throw FileError(name, "empty: no header line");
  if (d.points.empty()) throw FileError(name, "no data rows after the header");
  return d;
}

GonioData read_gonio_csv(const std::string& path) {
  const auto bytes = read_file_bytes(path, std::uint64_t{1} << 31);
  return parse_gonio_csv(
      std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), path);
}

std::string encode_gonio_csv(const GonioData& d) {
  std::string s = "theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,wavelength_nm,brdf_per_sr";
  if (d.has_sigma) s += ",brdf_sigma_per_sr";
  s += '\n';
  for (const auto& p : d.points) {
    s +=
        fmt::format("{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}", p.theta_i / kDeg,
                    p.phi_i / kDeg, p.theta_o / kDeg, p.phi_o / kDeg, p.wavelength_m * 1e9, p.brdf);
    if (d.has_sigma) s += fmt::format(",{:.17g}", p.sigma);
    s += '\n';
  }
  return s;
}

void write_gonio_csv(const GonioData& d, const std::string& path) {
  write_file_atomic(path, encode_gonio_csv(d));
}

}  // namespace microbrdf
