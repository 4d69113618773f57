#include "cli_checks.hpp"

#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string_view>

#include "microbrdf/error.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/io.hpp"
#include "microbrdf/units.hpp"

namespace microbrdf::cli {
namespace fs = std::filesystem;

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

std::string shown(double v) {
  char b[48];
  std::snprintf(b, sizeof b, "%g", v);
  return b;
}

/// `path` without trailing separators: "scene/" names the folder scene, whose parent is ".".
fs::path without_trailing_slash(const std::string& path) {
  fs::path p(path);
  while (!p.has_filename() && p.has_relative_path()) p = p.parent_path();
  return p;
}

/// The folder a new file or folder at `path` would be created in.
fs::path parent_of(const std::string& path) {
  fs::path p = without_trailing_slash(path).parent_path();
  return p.empty() ? fs::path(".") : p;
}

}  // namespace

void Preflight::add(std::string_view flag, const std::string& problem) {
  problems_.push_back(std::string(flag) + ": " + problem);
}

void Preflight::writable_parent(std::string_view flag, const std::string& path) {
  const fs::path dir = parent_of(path);
  std::error_code ec;
  // The rule of every command (docs/guide.md, "Output files and folders"): an output's folder
  // must exist; only the last component of an output folder is created. A typo in a folder name
  // then fails at once instead of scattering results into a new tree.
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    add(flag, path + ": " + dir.string() + " is not a folder");
  else if (!fs::is_directory(dir, ec))
    add(flag, path + ": folder " + dir.string() + " does not exist (create it first: mkdir -p " +
                  dir.string() + ")");
  else if (access(dir.c_str(), W_OK) != 0)
    add(flag, path + ": folder " + dir.string() + " is not writable");
}

Preflight& Preflight::require(bool ok, std::string_view flag, const std::string& problem) {
  if (!ok) add(flag, problem);
  return *this;
}

Preflight& Preflight::input(std::string_view flag, const std::string& path) {
  std::error_code ec;
  if (path.empty()) {
    add(flag, "empty file name");
  } else if (!fs::exists(path, ec)) {
    add(flag, path + ": no such file or folder");
  } else if (access(path.c_str(), R_OK) != 0) {
    add(flag, path + ": not readable (permissions)");
  }
  return *this;
}

Preflight& Preflight::output(std::string_view flag, const std::string& path,
                             std::initializer_list<std::string_view> extensions) {
  const std::string ext = lower(fs::path(path).extension().string());
  bool known = false;
  std::string list;
  for (auto e : extensions) {
    known = known || ext == e;
    list += (list.empty() ? "" : ", ") + std::string(e);
  }
  std::error_code ec;
  if (path.empty()) {
    add(flag, "empty file name");
  } else if (!known) {
    add(flag, path + ": unknown extension '" + ext + "' (expected " + list + ")");
  } else if (fs::is_directory(path, ec)) {
    add(flag, path + ": is a folder, not a file");
  } else {
    writable_parent(flag, path);
  }
  return *this;
}

Preflight& Preflight::height_map_output(std::string_view flag, const std::string& path) {
  const SurfaceFormat f = format_from_extension(path);
  std::error_code ec;
  if (path.empty())
    add(flag, "empty file name");
  else if (f == SurfaceFormat::Auto)
    add(flag, path + ": cannot write a height map as '" + fs::path(path).extension().string() +
                  "' (writable: .x3p .gwy .npy .xyz .txt .asc .csv)");
  else if (!format_can_write(f))
    add(flag, path + ": writing " + format_name(f) +
                  " is not supported (writable: .x3p .gwy .npy .xyz .txt .asc .csv)");
  else if (fs::is_directory(path, ec))
    add(flag, path + ": is a folder, not a file");
  else
    writable_parent(flag, path);
  return *this;
}

Preflight& Preflight::output_dir(std::string_view flag, const std::string& path) {
  std::error_code ec;
  if (path.empty()) {
    add(flag, "empty folder name");
  } else if (fs::exists(path, ec)) {
    if (!fs::is_directory(path, ec))
      add(flag, path + ": exists and is not a folder");
    else if (access(path.c_str(), W_OK) != 0)
      add(flag, path + ": folder is not writable");
  } else {
    writable_parent(flag, path);
  }
  return *this;
}

Preflight& Preflight::envmap(std::string_view flag, const std::string& path) {
  const std::size_t before = problems_.size();
  input(flag, path);
  if (problems_.size() != before) return *this;
  std::ifstream in(path, std::ios::binary);
  char head[10] = {};
  in.read(head, sizeof head);
  const std::string_view h(head, static_cast<std::size_t>(in.gcount()));
  const bool exr = h.size() >= 4 && static_cast<unsigned char>(h[0]) == 0x76 &&
                   static_cast<unsigned char>(h[1]) == 0x2f &&
                   static_cast<unsigned char>(h[2]) == 0x31 &&
                   static_cast<unsigned char>(h[3]) == 0x01;
  const bool radiance = h.substr(0, 2) == "#?";
  if (fs::is_directory(path))
    add(flag, path + ": is a folder, not an environment map");
  else if (!exr && !radiance)
    add(flag, path + ": not an OpenEXR or Radiance .hdr file (wrong signature)");
  return *this;
}

Preflight& Preflight::metal(std::string_view flag, const std::string& name) {
  try {
    (void)microbrdf::metal(name);
  } catch (const std::exception& e) {
    add(flag, e.what());
  }
  return *this;
}

Preflight& Preflight::positive(std::string_view flag, double value) {
  if (!(value > 0) || !std::isfinite(value)) add(flag, "must be > 0 (got " + shown(value) + ")");
  return *this;
}

Preflight& Preflight::in_range(std::string_view flag, double value, double lo, double hi) {
  if (!(value >= lo && value <= hi))
    add(flag, "must be in [" + shown(lo) + ", " + shown(hi) + "] (got " + shown(value) + ")");
  return *this;
}

void Preflight::done() const {
  if (problems_.empty()) return;
  std::string all;
  for (const auto& p : problems_) all += (all.empty() ? "" : "; ") + p;
  throw InputError(all);
}

namespace {
/// Parses the whole of `text` as a number into `v`; returns an error message or "".
std::string parse_number(const std::string& text, double& v) {
  try {
    std::size_t used = 0;
    v = std::stod(text, &used);
    if (used == text.size()) return {};
  } catch (const std::exception&) {
  }
  return "not a number: '" + text + "'";
}
}  // namespace

CLI::Validator positive_number(double hi) {
  const std::string range = std::isfinite(hi) ? "in (0, " + shown(hi) + "]" : "> 0";
  return CLI::Validator(
      [hi, range](std::string& text) -> std::string {
        double v = 0;
        if (auto e = parse_number(text, v); !e.empty()) return e;
        if (!(v > 0) || !std::isfinite(v) || v > hi)
          return "must be " + range + " (got " + text + ")";
        return {};
      },
      range, "POSITIVE");
}

CLI::Validator number_in(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        double v = 0;
        if (auto e = parse_number(text, v); !e.empty()) return e;
        if (!(v >= lo && v <= hi))
          return "must be in [" + shown(lo) + ", " + shown(hi) + "] (got " + text + ")";
        return {};
      },
      "in [" + shown(lo) + ", " + shown(hi) + "]", "RANGE");
}

CLI::Validator count_in(double lo, double hi, std::string why) {
  return CLI::Validator(
      [lo, hi, why](std::string& text) -> std::string {
        double v = 0;
        if (auto e = parse_number(text, v); !e.empty()) return e;
        if (!(v >= lo && v <= hi) || v != std::floor(v))
          return "must be a whole number in [" + shown(lo) + ", " + shown(hi) + "] (got " + text +
                 ")" + (why.empty() || !(v > hi) ? "" : ": " + why);
        return {};
      },
      "in [" + shown(lo) + ", " + shown(hi) + "]", "COUNT");
}

namespace {
// Runs `parse` on `text` and turns its InputError into a validator's message.
template <class Parse>
std::string parsed(Parse parse, const std::string& text) {
  try {
    parse(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return {};
}

std::string length_range(double lo, double hi) {
  return (lo == 0 ? std::string("0") : format_length(lo)) + " .. " + format_length(hi);
}

std::string check_length(double v, double lo, double hi, const std::string& text) {
  if (v >= lo && v <= hi) return {};
  return "must lie in " + length_range(lo, hi) + " (got " + text + ")";
}
}  // namespace

CLI::Validator length_in(double lo, double hi, std::initializer_list<const char*> words) {
  std::vector<std::string> ok(words.begin(), words.end());
  return CLI::Validator(
      [lo, hi, ok](std::string& text) -> std::string {
        if (std::find(ok.begin(), ok.end(), text) != ok.end()) return {};
        double v = 0;
        if (auto e = parsed([&](const std::string& t) { v = parse_length(t); }, text); !e.empty())
          return e;
        return check_length(v, lo, hi, text);
      },
      length_range(lo, hi), "LENGTH");
}

CLI::Validator length_pair_in(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        LengthPair p;
        if (auto e = parsed([&](const std::string& t) { p = parse_length_pair(t); }, text);
            !e.empty())
          return e;
        if (auto e = check_length(p.x, lo, hi, text); !e.empty()) return e;
        return check_length(p.y, lo, hi, text);
      },
      length_range(lo, hi), "SIZE");
}

CLI::Validator length_or_pair_in(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        LengthPair p;
        if (auto e = parsed([&](const std::string& t) { p = parse_length_or_pair(t); }, text);
            !e.empty())
          return e;
        if (auto e = check_length(p.x, lo, hi, text); !e.empty()) return e;
        return check_length(p.y, lo, hi, text);
      },
      length_range(lo, hi), "LENGTH");
}

CLI::Validator height() { return length_in(0, kMaxLength); }
CLI::Validator distance() { return length_in(kMinLength, kMaxLength); }
CLI::Validator direction() { return angle_in(-2 * M_PI, 2 * M_PI); }
CLI::Validator polar_angle() { return angle_in(0, M_PI / 2); }
CLI::Validator wavelength() { return length_in(100e-9, 20e-6); }

CLI::Validator angle_in(double lo, double hi, bool list) {
  const double deg = 180 / M_PI;
  const std::string range = shown(lo * deg) + " .. " + shown(hi * deg) + " deg";
  return CLI::Validator(
      [lo, hi, list, range](std::string& text) -> std::string {
        std::vector<std::string> items{text};
        if (list) {
          items.clear();
          std::size_t start = 0;
          for (std::size_t comma; (comma = text.find(',', start)) != std::string::npos;
               start = comma + 1)
            items.push_back(text.substr(start, comma - start));
          items.push_back(text.substr(start));
        }
        for (const auto& item : items) {
          double v = 0;
          if (auto e = parsed([&](const std::string& t) { v = parse_angle(t); }, item); !e.empty())
            return e;
          if (!(v >= lo - 1e-12 && v <= hi + 1e-12))
            return "must lie in " + range + " (got " + item + ")";
        }
        return {};
      },
      range, "ANGLE");
}

namespace {
// A count or a size: plain decimal digits that fit 64 bits, no sign. Leading zeros are dropped,
// so that CLI11's base-0 conversion cannot read the rest as octal.
CLI::Validator decimal_count() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const std::size_t start = !text.empty() && text[0] == '+' ? 1 : 0;
        const auto digits = std::string_view(text).substr(start);
        const bool plain = !digits.empty() && std::all_of(digits.begin(), digits.end(), [](char c) {
          return c >= '0' && c <= '9';
        });
        std::uint64_t v = 0;
        const bool fits =
            plain &&
            std::from_chars(digits.data(), digits.data() + digits.size(), v).ec == std::errc();
        if (!fits)
          return "must be a whole number >= 0 (a count or a size) that fits in 64 bits (got " +
                 text + ")";
        text =
            std::string(digits.substr(std::min(digits.find_first_not_of('0'), digits.size() - 1)));
        return {};
      },
      "", "DECIMAL_COUNT");
}
}  // namespace

void guard_integer_options(CLI::App& app) {
  // Every integer option of the command line is a count or a size (threads, rays, samples,
  // pixels, orders, seeds): none takes a negative value.
  for (CLI::Option* o : app.get_options()) {
    // (Validators append their descriptions: "UINT:in [1, 1e+10]".)
    const std::string type = o->get_type_name().substr(0, o->get_type_name().find(':'));
    if (type == "UINT" || type == "INT") o->transform(decimal_count());  // it rewrites "010"
  }
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
    guard_integer_options(*sub);
}

std::string number_or_na(double v, const char* format) {
  if (!std::isfinite(v)) return "n/a";
  char b[64];
  std::snprintf(b, sizeof b, format, v);
  return b;
}

}  // namespace microbrdf::cli
