#include "cli_common.hpp"

#include <cctype>
#include <cstdio>
#include <iostream>

#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/scanset.hpp"
#include "microbrdf/units.hpp"

namespace microbrdf::cli {

void add_read_flags(CLI::App* cmd, ReadFlags& flags, const std::string& default_level) {
  flags.level = default_level;
  cmd->add_option(
         "--spacing", flags.spacing,
         "Sample spacing, overriding or supplying what the file lacks: 110nm, or 110x130nm "
         "for dx x dy (needed for .exr/.tif and .npy without a JSON sidecar)")
      ->check(length_or_pair_in(kMinLength, kMaxLength));
  cmd->add_option("--z-scale", flags.z_scale,
                  "Height of one stored unit, for files that store no height unit (integer or "
                  "float TIFF, EXR, .npy, text grids), e.g. 1nm: the file's numbers are "
                  "nanometres; integer TIFF images need it")
      ->check(length_in(kMinLength, kMaxLength));
  cmd->add_option(
         "--level", flags.level,
         "Levelling before anything else: none | plane (least-squares plane) | poly2..poly6 "
         "(2-D polynomial of that total degree)")
      ->capture_default_str();
}

ReadOptions read_options(const ReadFlags& flags) {
  ReadOptions o;
  if (!flags.spacing.empty()) {
    const LengthPair p = parse_length_or_pair(flags.spacing);
    o.dx = p.x;
    o.dy = p.y;
  }
  if (!flags.z_scale.empty()) o.z_scale = parse_length(flags.z_scale);
  return o;
}

namespace {
void warn_if_sparse(const std::string& path, std::size_t valid, std::size_t nx, std::size_t ny) {
  const double f = double(valid) / double(std::max<std::size_t>(1, nx * ny));
  if (f < kSparseValidFraction)
    std::fprintf(stderr,
                 "microbrdf: %s: warning: only %.3g%% of the samples are valid (%zu of %zu x "
                 "%zu); statistics rest on few points\n",
                 path.c_str(), 100 * f, valid, nx, ny);
}

}  // namespace

void SampleTally::add(const std::string& path, const nlohmann::json& scan) {
  const auto nx = scan.at("nx").get<std::size_t>(), ny = scan.at("ny").get<std::size_t>();
  const auto valid = scan.at("valid").get<std::size_t>();
  all += nx * ny;
  invalid += nx * ny - valid;
  warn_if_sparse(path, valid, nx, ny);
}

void SampleTally::print(const char* command) const {
  std::fprintf(stderr, "microbrdf %s: %zu of %zu height samples invalid (%.3g%%), skipped\n",
               command, invalid, all, all ? 100.0 * double(invalid) / double(all) : 0.0);
}

void warn_if_sparse(const std::string& path, const Surface& s) {
  warn_if_sparse(path, s.valid_count(), s.nx, s.ny);
}

std::vector<std::string> scan_inputs(const std::vector<std::string>& inputs) {
  auto paths = expand_scan_inputs(inputs);
  Preflight pre;
  for (const auto& p : paths) pre.input("input", p);
  pre.done();
  return paths;
}

Surface load_surface(const std::string& path, const ReadFlags& flags, std::string* report) {
  auto spec = LevelingSpec::parse(flags.level);  // validate before the (maybe long) read
  Preflight().input("input", path).done();
  Surface s = read_surface(path, read_options(flags));
  warn_if_sparse(path, s);
  auto r = about_file(path, [&] { return level_surface(s, spec); });
  if (report) *report = r.description;
  return s;
}

void check_plot_name(const std::string& flag, const std::string& path) {
  if (path.empty()) return;
  const auto dot = path.find_last_of('.');
  std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext != "png" && ext != "svg")
    throw InputError(flag + " " + path + ": plots are written as .png or .svg");
}

void emit_text(const std::string& path, const std::string& text) {
  if (path == "-") {
    std::fwrite(text.data(), 1, text.size(), stdout);
    return;
  }
  write_file_atomic(path, text);
}

void print_json(const nlohmann::json& j) {
  std::string text;
  try {
    text = j.dump(2);
  } catch (const nlohmann::json::type_error& e) {
    // JSON text is UTF-8: a name with other bytes cannot be written into it (refused, not
    // mangled). The outputs of the run are not committed either.
    throw InputError(std::string("--json: a file name holds bytes that are not UTF-8, which JSON "
                                 "cannot hold; rename the file or leave out --json (") +
                     e.what() + ")");
  }
  std::cout << text << std::endl;
}

void progress(const char* command, std::size_t index, std::size_t total, const std::string& what) {
  Progress(command).item(index, total, what);
}

}  // namespace microbrdf::cli
