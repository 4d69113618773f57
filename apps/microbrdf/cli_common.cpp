#include "cli_common.hpp"

#include <cstdio>
#include <iostream>

#include "microbrdf/error.hpp"
#include "microbrdf/units.hpp"

namespace microbrdf::cli {

void add_read_flags(CLI::App* cmd, ReadFlags& flags, const std::string& default_level) {
  flags.level = default_level;
  cmd->add_option(
      "--spacing", flags.spacing,
      "Sample spacing, overriding or supplying what the file lacks: 110nm, or 110x130nm "
      "for dx x dy (needed for .exr/.tif and .npy without a JSON sidecar)");
  cmd->add_option(
         "--level", flags.level,
         "Levelling before anything else: none | plane (least-squares plane) | poly2..poly6 "
         "(2-D polynomial of that total degree)")
      ->capture_default_str();
}

ReadOptions read_options(const ReadFlags& flags) {
  ReadOptions o;
  if (!flags.spacing.empty()) {
    if (flags.spacing.find('x') != std::string::npos) {
      auto p = parse_length_pair(flags.spacing);
      o.dx = p.x;
      o.dy = p.y;
    } else {
      o.dx = o.dy = parse_length(flags.spacing);
    }
  }
  return o;
}

void warn_if_sparse(const std::string& path, const Surface& s) {
  const double f = s.valid_fraction();
  if (f < kSparseValidFraction)
    std::fprintf(stderr,
                 "microbrdf: %s: warning: only %.3g%% of the samples are valid (%zu of %zu x "
                 "%zu); statistics rest on few points\n",
                 path.c_str(), 100 * f, s.valid_count(), s.nx, s.ny);
}

Surface load_surface(const std::string& path, const ReadFlags& flags, std::string* report) {
  auto spec = LevelingSpec::parse(flags.level);  // validate before the (maybe long) read
  Surface s = read_surface(path, read_options(flags));
  warn_if_sparse(path, s);
  auto r = about_file(path, [&] { return level_surface(s, spec); });
  if (report) *report = r.description;
  return s;
}

nlohmann::json stats_json(const std::string& path, const Surface& s, const SurfaceStats& st) {
  nlohmann::json j = microbrdf::stats_json(st);
  j["path"] = path;
  j["format"] = s.meta.format;
  j["invalid_count"] = s.size() - st.valid_count;
  j["leveling"] = s.meta.leveling;
  j["z0_m"] = s.z0;
  j["instrument"] = s.meta.instrument;
  j["date"] = s.meta.date;
  j["z_unit_in_file"] = s.meta.z_unit_in_file;
  return j;
}

NdfSpec ndf_spec(const ModelFlags& f) {
  NdfSpec s;
  s.model = f.model;
  s.alpha_x = f.alpha_x > 0 ? f.alpha_x : f.alpha;
  s.alpha_y = f.alpha_y > 0 ? f.alpha_y : (f.alpha > 0 ? f.alpha : s.alpha_x);
  if (!(s.alpha_x > 0))
    throw InputError("give the roughness: --alpha, or --alpha-x (and --alpha-y)");
  s.phi = parse_angle(f.phi);
  s.theta_x = parse_angle(f.theta_x);
  s.theta_y = parse_angle(f.theta_y);
  s.theta_z = parse_angle(f.theta_z);
  return s;
}

CLI::Option* add_model_flags(CLI::App* c, ModelFlags& f) {
  auto* model =
      c->add_option("--model", f.model, "NDF: beckmann, ggx or ellipsoid")->capture_default_str();
  c->add_option("--alpha", f.alpha, "Roughness alpha (both axes)");
  c->add_option("--alpha-x", f.alpha_x, "Roughness along the first axis");
  c->add_option("--alpha-y", f.alpha_y, "Roughness along the second axis (default: = alpha-x)");
  c->add_option("--phi", f.phi, "beckmann/ggx: azimuth of the alpha-x axis (deg unless marked)");
  c->add_option("--theta-x", f.theta_x, "ellipsoid: rotation Rx (tilts the peak towards +y)");
  c->add_option("--theta-y", f.theta_y, "ellipsoid: rotation Ry (tilts the peak towards -x)");
  c->add_option("--theta-z", f.theta_z, "ellipsoid: rotation Rz (turns the axes by -theta_z)");
  return model;
}

void print_json(const nlohmann::json& j) { std::cout << j.dump(2) << std::endl; }

void progress(const char* command, std::size_t index, std::size_t total, const std::string& what) {
  if (total <= 1) return;
  std::fprintf(stderr, "microbrdf %s: [%zu/%zu] %s\n", command, index + 1, total, what.c_str());
}

}  // namespace microbrdf::cli
