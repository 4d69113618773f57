// ASCII height data: "x y z" triples (.xyz) and plain height matrices (.txt/.asc/.csv).
//
// Lexical rules (both forms):
//  - values are separated by whitespace, ',' or ';' (runs of separators count as one, so an
//    empty CSV field is not a value); a leading '+' is allowed; in a line that contains ';',
//    ',' is a decimal comma ("1,5;2,5" = 1.5 and 2.5);
//  - "nan" (any case, also "-nan"), "inf", "-", "--", "*", "***", "NA", "N/A" mark an invalid
//    point;
//  - lines whose first non-blank character is '#' or '%' are comments; a comment of the form
//    "key = value" or "key: value" is a header entry (see below);
//  - the first non-comment line may be a column header made only of non-numbers ("x,y,z").
//
// Header entries understood (keys are case-insensitive):
//  - "microbrdf grid" / "microbrdf xyz": the form of the file (written by our writers);
//  - nx, ny: grid size (checked against the data);
//  - dx_m, dy_m, x0_m, y0_m: spacing and origin in metres;
//  - units (or unit): length unit of x, y and z ("m", "mm", "um", "µm", "nm", "pm", ...);
//  - xy_unit, z_unit: the same for x/y or z alone; z_unit also applies to a height matrix;
//  - title: copied to SurfaceMetadata::comment.
// Without a unit entry every coordinate and height is taken as metres (meta "unit_warning").
//
// Which form: a "microbrdf grid|xyz" header decides; else a name ending in ".xyz" means XYZ;
// else a file whose rows all hold exactly 3 values is XYZ when it has at least 4 rows, its
// first two columns form a regular grid of at least 2 x 2 nodes that the rows fill to >= 50 %
// without duplicates; anything else is a height matrix (one row of the surface per line).
//
// XYZ: the distinct x (and y) values, merged when closer than 1e-6 of their magnitude (print
// noise), must lie on a lattice c0 + k*d to 10 % of d. Every gap between neighbouring values
// counts as round(gap / smallest gap) steps and d = span / steps, so whole missing columns are
// allowed and print noise in one gap does not skew d. Points may come in any order; grid nodes
// without a point are invalid; row 0 is the smallest y. Exact dx_m/x0_m header values are preferred
// when they agree with the data.
//
// Writers print %.17g, so read(write(s)) reproduces heights, spacing and origin bit for bit.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/byte_reader.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/file_size_limit.hpp"
#include "microbrdf/units.hpp"
#include "surface/formats.hpp"

namespace microbrdf::detail {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string lower(std::string_view s) {
  std::string o(s);
  for (auto& ch : o) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return o;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

// In a line that contains ';', ',' is a decimal comma ("1,5;2,5"), not a separator.
bool is_sep(char ch, bool decimal_comma) {
  return ch == ' ' || ch == '\t' || (ch == ',' && !decimal_comma) || ch == ';' || ch == '\r' ||
         ch == '\v' || ch == '\f';
}

// A value token -> number (NaN for invalid markers); nullopt when it is not a number at all.
std::optional<double> parse_value(std::string_view t) {
  if (t == "-" || t == "--" || t == "*" || t == "***" || t == "NA" || t == "N/A" || t == "n/a")
    return kNaN;
  if (t.size() > 1 && t[0] == '+' && t[1] != '-') t.remove_prefix(1);
  double v = 0;
  auto res = std::from_chars(t.data(), t.data() + t.size(), v);
  if (res.ec == std::errc::result_out_of_range) return kNaN;
  if (res.ec != std::errc() || res.ptr != t.data() + t.size()) return std::nullopt;
  return v;
}

struct Text {
  std::map<std::string, std::string> header;  // lower-case key -> value
  std::string mode;                           // "grid", "xyz" or "" (from the header)
  std::size_t cols = 0;
  std::size_t rows = 0;
  std::vector<double> values;  // rows * cols, row-major
};

Text tokenize(const ByteReader& r) {
  Text t;
  std::string_view all(reinterpret_cast<const char*>(r.data().data()), r.size());
  if (all.substr(0, 3) == "\xEF\xBB\xBF") all.remove_prefix(3);  // UTF-8 BOM
  std::size_t line_no = 0;
  std::size_t first_row_line = 0;
  bool header_line_seen = false;
  std::vector<std::string_view> toks;
  while (!all.empty()) {
    ++line_no;
    std::size_t nl = all.find('\n');
    std::string_view line = all.substr(0, nl);
    all.remove_prefix(nl == std::string_view::npos ? all.size() : nl + 1);
    line = trim(line);
    if (line.empty()) continue;
    if (line[0] == '#' || line[0] == '%') {
      std::string_view body = trim(line.substr(1));
      std::string lb = lower(body);
      if (lb == "microbrdf grid") t.mode = "grid";
      if (lb == "microbrdf xyz") t.mode = "xyz";
      std::size_t eq = body.find_first_of("=:");
      if (eq != std::string_view::npos && eq > 0) {
        std::string key = lower(trim(body.substr(0, eq)));
        if (key.size() <= 32 && !t.header.count(key))
          t.header[key] = std::string(trim(body.substr(eq + 1)));
      }
      continue;
    }
    if (line.find('\0') != std::string_view::npos)
      r.fail("line " + std::to_string(line_no) + ": binary data (NUL byte) in a text file");
    toks.clear();
    const bool decimal_comma = line.find(';') != std::string_view::npos;
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && is_sep(line[i], decimal_comma)) ++i;
      std::size_t j = i;
      while (j < line.size() && !is_sep(line[j], decimal_comma)) ++j;
      if (j > i) toks.push_back(line.substr(i, j - i));
      i = j;
    }
    if (toks.empty()) continue;
    const std::size_t before = t.values.size();
    bool all_words = true;
    std::string bad;
    std::string comma_fixed;
    for (auto tok : toks) {
      if (decimal_comma && tok.find(',') != std::string_view::npos) {
        comma_fixed.assign(tok);
        std::replace(comma_fixed.begin(), comma_fixed.end(), ',', '.');
        tok = comma_fixed;
      }
      auto v = parse_value(tok);
      if (v) {
        all_words = false;
        t.values.push_back(*v);
      } else if (bad.empty()) {
        bad = std::string(tok.substr(0, 40));
      }
    }
    if (!bad.empty()) {
      if (all_words && t.rows == 0 && !header_line_seen) {  // a column header such as "x,y,z"
        header_line_seen = true;
        t.values.resize(before);
        continue;
      }
      r.fail("line " + std::to_string(line_no) + ": cannot read '" + bad + "' as a number");
    }
    const std::size_t n = t.values.size() - before;
    if (t.rows == 0) {
      t.cols = n;
      first_row_line = line_no;
    } else if (n != t.cols) {
      r.fail("line " + std::to_string(line_no) + " has " + std::to_string(n) +
             " values, but line " + std::to_string(first_row_line) + " has " +
             std::to_string(t.cols) + " (all rows must have the same length)");
    }
    ++t.rows;
  }
  if (t.rows == 0) r.fail("no numeric data in the text file");
  return t;
}

struct Units {
  double xy = 1.0, z = 1.0;
  std::string xy_name = "m", z_name = "m";
  bool stated = false;
};

double unit_scale(const ByteReader& r, const std::string& u) {
  double s = length_unit_to_metres(u);
  if (s == 0)
    r.fail("unknown length unit '" + u.substr(0, 40) + "' in the header (use m, mm, um, nm, pm)");
  return s;
}

Units header_units(const ByteReader& r, const Text& t) {
  Units u;
  for (const char* k : {"units", "unit"}) {
    auto it = t.header.find(k);
    if (it != t.header.end()) {
      u.xy = u.z = unit_scale(r, it->second);
      u.xy_name = u.z_name = it->second;
      u.stated = true;
      break;
    }
  }
  if (auto it = t.header.find("xy_unit"); it != t.header.end()) {
    u.xy = unit_scale(r, it->second);
    u.xy_name = it->second;
    u.stated = true;
  }
  if (auto it = t.header.find("z_unit"); it != t.header.end()) {
    u.z = unit_scale(r, it->second);
    u.z_name = it->second;
    u.stated = true;
  }
  return u;
}

std::optional<double> header_double(const ByteReader& r, const Text& t, const char* key) {
  auto it = t.header.find(key);
  if (it == t.header.end()) return std::nullopt;
  auto v = parse_value(it->second);
  if (!v || !std::isfinite(*v))
    r.fail(std::string("header entry '") + key + "' is not a finite number: '" +
           it->second.substr(0, 40) + "'");
  return v;
}

std::optional<std::uint64_t> header_count(const ByteReader& r, const Text& t, const char* key) {
  auto it = t.header.find(key);
  if (it == t.header.end()) return std::nullopt;
  std::uint64_t v = 0;
  const std::string& s = it->second;
  auto res = std::from_chars(s.data(), s.data() + s.size(), v);
  if (res.ec != std::errc() || res.ptr != s.data() + s.size() || v == 0)
    r.fail(std::string("header entry '") + key + "' is not a positive integer: '" +
           s.substr(0, 40) + "'");
  return v;
}

struct Axis {
  double c0 = 0;
  double d = 0;  // 0 when all values are equal
  std::size_t n = 1;
};

// Derives a regular lattice from coordinate values; nullopt (with `why`) if there is none.
std::optional<Axis> derive_axis(std::vector<double> v, const char* label, std::string& why) {
  std::sort(v.begin(), v.end());
  const double mag = std::max(std::fabs(v.front()), std::fabs(v.back()));
  const double tol = 1e-6 * mag;
  std::vector<double> centres;
  for (double x : v)
    if (centres.empty() || x - centres.back() > tol) centres.push_back(x);
  Axis a;
  a.c0 = centres.front();
  if (centres.size() == 1) return a;
  double gmin = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i < centres.size(); ++i)
    gmin = std::min(gmin, centres[i] - centres[i - 1]);
  const double span = centres.back() - centres.front();
  if (!(span / gmin < 4.0e9)) {
    why = std::string(label) + " values span " + std::to_string(span / gmin) +
          " times their smallest gap: not a regular grid";
    return std::nullopt;
  }
  // Each gap is a whole number of steps (missing columns allowed); count the steps so that
  // print noise in the smallest gap does not skew the spacing.
  double steps = 0;
  for (std::size_t i = 1; i < centres.size(); ++i)
    steps += std::round((centres[i] - centres[i - 1]) / gmin);
  const auto nsteps = static_cast<std::size_t>(steps);
  a.n = nsteps + 1;
  a.d = span / static_cast<double>(nsteps);
  for (double c : centres) {
    double k = std::round((c - a.c0) / a.d);
    if (std::fabs(c - a.c0 - k * a.d) > 0.1 * a.d) {
      char buf[200];
      std::snprintf(buf, sizeof buf,
                    "%s values are not on a regular grid: %.10g is off the lattice %.10g + k * "
                    "%.10g",
                    label, c, a.c0, a.d);
      why = buf;
      return std::nullopt;
    }
  }
  return a;
}

// Builds a surface from x y z rows; nullopt (with `why`) when the rows are not a regular grid.
// `heuristic`: stricter acceptance (used when the file did not say it is XYZ).
std::optional<Surface> build_xyz(const ByteReader& r, const Text& t, const Units& u,
                                 const ReadOptions& opt, bool heuristic, std::string& why) {
  if (t.cols != 3) {
    why = "XYZ data needs 3 values per line, found " + std::to_string(t.cols);
    return std::nullopt;
  }
  const std::size_t np = t.rows;
  if (heuristic && np < 4) {
    why = "too few rows";
    return std::nullopt;
  }
  std::vector<double> xs(np), ys(np);
  for (std::size_t i = 0; i < np; ++i) {
    xs[i] = t.values[3 * i] * u.xy;
    ys[i] = t.values[3 * i + 1] * u.xy;
    if (!std::isfinite(xs[i]) || !std::isfinite(ys[i])) {
      why = "row " + std::to_string(i + 1) + " has a non-finite x or y coordinate";
      return std::nullopt;
    }
  }
  auto ax = derive_axis(xs, "x", why);
  if (!ax) return std::nullopt;
  auto ay = derive_axis(ys, "y", why);
  if (!ay) return std::nullopt;
  if (heuristic && (ax->n < 2 || ay->n < 2)) {
    why = "fewer than 2 distinct x or y values";
    return std::nullopt;
  }
  const double cells = static_cast<double>(ax->n) * static_cast<double>(ay->n);
  if (cells > (heuristic ? 2.0 : 10.0) * static_cast<double>(np)) {
    why = "the points fill only " + std::to_string(100.0 * static_cast<double>(np) / cells) +
          " % of the " + std::to_string(ax->n) + " x " + std::to_string(ay->n) +
          " grid they span (need " + (heuristic ? "50" : "10") + " %)";
    return std::nullopt;
  }
  check_grid(r, ax->n, ay->n, 0, 0);

  // Exact values from our own header when they agree with the data.
  auto refine = [&](Axis& a, const char* dkey, const char* okey, std::optional<double> fallback,
                    const char* label) -> bool {
    auto hd = header_double(r, t, dkey);
    if (a.n == 1) {
      if (hd && *hd > 0)
        a.d = *hd;
      else if (fallback)
        a.d = *fallback;
      else {
        why = std::string("all ") + label + " values are equal, so the " + label +
              " spacing is unknown: pass --spacing";
        return false;
      }
    } else if (hd && std::fabs(*hd - a.d) <= 1e-6 * a.d) {
      a.d = *hd;
    }
    if (auto ho = header_double(r, t, okey); ho && std::fabs(*ho - a.c0) <= 0.01 * a.d) a.c0 = *ho;
    return true;
  };
  if (!refine(*ax, "dx_m", "x0_m", opt.dx, "x")) return std::nullopt;
  if (!refine(*ay, "dy_m", "y0_m", opt.dy ? opt.dy : opt.dx, "y")) return std::nullopt;

  Surface s;
  s.nx = ax->n;
  s.ny = ay->n;
  s.dx = ax->d;
  s.dy = ay->d;
  s.x0 = ax->c0;
  s.y0 = ay->c0;
  s.z.assign(s.nx * s.ny, kNaN);
  s.valid.assign(s.nx * s.ny, 0);
  std::vector<std::uint8_t> seen(s.nx * s.ny, 0);
  for (std::size_t i = 0; i < np; ++i) {
    const double fx = s.nx == 1 ? 0.0 : (xs[i] - s.x0) / s.dx;
    const double fy = s.ny == 1 ? 0.0 : (ys[i] - s.y0) / s.dy;
    const double kx = std::round(fx), ky = std::round(fy);
    if (std::fabs(fx - kx) > 0.25 || std::fabs(fy - ky) > 0.25 || kx < 0 || ky < 0 ||
        kx >= static_cast<double>(s.nx) || ky >= static_cast<double>(s.ny)) {
      why = "row " + std::to_string(i + 1) + " is off the regular grid";
      return std::nullopt;
    }
    const std::size_t k = static_cast<std::size_t>(ky) * s.nx + static_cast<std::size_t>(kx);
    if (seen[k]) {
      why = "row " + std::to_string(i + 1) + " repeats the point (" + std::to_string(kx) + ", " +
            std::to_string(ky) + ") of the grid";
      return std::nullopt;
    }
    seen[k] = 1;
    s.z[k] = t.values[3 * i + 2] * u.z;
    s.valid[k] = 1;
  }
  if (auto hn = header_count(r, t, "nx"); hn && *hn != s.nx)
    r.fail("header says nx = " + std::to_string(*hn) + " but the x values span " +
           std::to_string(s.nx) + " columns");
  if (auto hn = header_count(r, t, "ny"); hn && *hn != s.ny)
    r.fail("header says ny = " + std::to_string(*hn) + " but the y values span " +
           std::to_string(s.ny) + " rows");
  s.meta.format = "xyz";
  return s;
}

Surface build_grid(const ByteReader& r, const Text& t, const Units& u, const ReadOptions& opt) {
  check_grid(r, t.cols, t.rows, 0, 0);
  if (auto hn = header_count(r, t, "nx"); hn && *hn != t.cols)
    r.fail("header says nx = " + std::to_string(*hn) + " but the rows have " +
           std::to_string(t.cols) + " values");
  if (auto hn = header_count(r, t, "ny"); hn && *hn != t.rows)
    r.fail("header says ny = " + std::to_string(*hn) + " but there are " + std::to_string(t.rows) +
           " rows");
  Surface s;
  s.nx = t.cols;
  s.ny = t.rows;
  auto hdx = header_double(r, t, "dx_m");
  auto hdy = header_double(r, t, "dy_m");
  if (hdx) {
    s.dx = *hdx;
    s.dy = hdy ? *hdy : *hdx;
  } else if (opt.dx) {
    s.dx = *opt.dx;
    s.dy = opt.dy ? *opt.dy : *opt.dx;
  } else {
    r.fail(
        "a text height matrix stores no sample spacing: pass --spacing (e.g. 110nm) or add a "
        "'# dx_m = ...' header line");
  }
  if (auto v = header_double(r, t, "x0_m")) s.x0 = *v;
  if (auto v = header_double(r, t, "y0_m")) s.y0 = *v;
  s.z.resize(t.values.size());
  for (std::size_t i = 0; i < s.z.size(); ++i) s.z[i] = t.values[i] * u.z;
  s.valid.assign(s.z.size(), 1);
  s.meta.format = "txt";
  return s;
}

bool ends_with_xyz(const std::string& name) {
  return name.size() >= 4 && lower(name.substr(name.size() - 4)) == ".xyz";
}

// --- writing ---

class TextOut {
 public:
  explicit TextOut(const std::string& path) : path_(path), f_(std::fopen(path.c_str(), "wb")) {
    if (!f_) throw FileError(path, std::string("cannot create: ") + std::strerror(errno));
  }
  ~TextOut() {
    if (f_) std::fclose(f_);
  }
  TextOut(const TextOut&) = delete;
  TextOut& operator=(const TextOut&) = delete;
  void put(const std::string& s) {
    buf_ += s;
    flush_if_big();
  }
  void num(double v) {
    char b[40];
    int n = std::isfinite(v) ? std::snprintf(b, sizeof b, "%.17g", v)
                             : std::snprintf(b, sizeof b, "nan");
    buf_.append(b, static_cast<std::size_t>(n));
  }
  void ch(char c) {
    buf_.push_back(c);
    if (c == '\n') flush_if_big();
  }
  void close() {
    flush();
    std::FILE* f = f_;
    f_ = nullptr;
    if (std::fclose(f) != 0 || failed_) throw FileError(path_, write_failure_problem(errno));
  }

 private:
  void flush_if_big() {
    if (buf_.size() > (1u << 20)) flush();
  }
  void flush() {
    if (!buf_.empty() && std::fwrite(buf_.data(), 1, buf_.size(), f_) != buf_.size())
      failed_ = true;
    buf_.clear();
  }
  std::string path_;
  std::FILE* f_;
  std::string buf_;
  bool failed_ = false;
};

std::string one_line(std::string s) {
  for (auto& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}

void write_header(TextOut& o, const Surface& s, const char* kind) {
  char b[512];
  std::snprintf(b, sizeof b,
                "# microbrdf %s\n# nx = %zu\n# ny = %zu\n# dx_m = %.17g\n# dy_m = %.17g\n"
                "# x0_m = %.17g\n# y0_m = %.17g\n# z_unit = m\n",
                kind, s.nx, s.ny, s.dx, s.dy, s.x0, s.y0);
  o.put(b);
  if (!s.meta.comment.empty()) o.put("# title = " + one_line(s.meta.comment) + "\n");
}

}  // namespace

Surface read_ascii(Bytes data, const std::string& name, const ReadOptions& options) {
  ByteReader r(data, name);
  Text t = tokenize(r);
  Units u = header_units(r, t);
  std::string mode = t.mode;
  if (mode.empty() && ends_with_xyz(name)) mode = "xyz";
  Surface s;
  std::string why;
  if (mode == "xyz") {
    auto xs = build_xyz(r, t, u, options, false, why);
    if (!xs) r.fail("not a usable XYZ grid: " + why);
    s = std::move(*xs);
  } else if (mode == "grid") {
    s = build_grid(r, t, u, options);
  } else {
    std::optional<Surface> xs;
    if (t.cols == 3) xs = build_xyz(r, t, u, options, true, why);
    s = xs ? std::move(*xs) : build_grid(r, t, u, options);
  }
  const bool xyz = s.meta.format == "xyz";
  s.meta.z_unit_in_file = u.z_name;
  if (auto it = t.header.find("title"); it != t.header.end()) s.meta.comment = it->second;
  if (!u.stated)
    s.meta.set("unit_warning", xyz ? "no units stated in the file; x, y and z taken as metres"
                                   : "no z unit stated in the file; heights taken as metres");
  return s;
}

void write_ascii_grid(const Surface& s, const std::string& path) {
  TextOut o(path);
  write_header(o, s, "grid");
  for (std::size_t iy = 0; iy < s.ny; ++iy) {
    for (std::size_t ix = 0; ix < s.nx; ++ix) {
      if (ix) o.ch(' ');
      o.num(s.is_valid(s.index(ix, iy)) ? s.at(ix, iy) : kNaN);
    }
    o.ch('\n');
  }
  o.close();
}

void write_ascii_xyz(const Surface& s, const std::string& path) {
  TextOut o(path);
  write_header(o, s, "xyz");
  o.put("# columns: x_m y_m z_m (invalid points: nan)\n");
  for (std::size_t iy = 0; iy < s.ny; ++iy) {
    const double y = s.y0 + static_cast<double>(iy) * s.dy;
    for (std::size_t ix = 0; ix < s.nx; ++ix) {
      o.num(s.x0 + static_cast<double>(ix) * s.dx);
      o.ch(' ');
      o.num(y);
      o.ch(' ');
      o.num(s.is_valid(s.index(ix, iy)) ? s.at(ix, iy) : kNaN);
      o.ch('\n');
    }
  }
  o.close();
}

}  // namespace microbrdf::detail
