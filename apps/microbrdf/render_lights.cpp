// The light flags of `microbrdf render` (render_lights.hpp).
#include "render_lights.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "cli_checks.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/units.hpp"

namespace microbrdf::cli {
namespace {

/// "a,b,c,...:r,g,b" -> numbers before and after the colon.
void parse_light(const std::string& flag, const std::string& text, std::size_t n_geom,
                 std::vector<double>& geom, Eigen::Vector3d& rgb) {
  const auto colon = text.find(':');
  auto numbers = [&](std::string s) {
    std::replace(s.begin(), s.end(), ',', ' ');
    std::istringstream is(s);
    std::vector<double> v;
    double x;
    while (is >> x) v.push_back(x);
    if (!is.eof()) throw InputError(flag + " '" + text + "': not a list of numbers");
    return v;
  };
  if (colon == std::string::npos)
    throw InputError(flag + " '" + text + "': expected GEOMETRY:R,G,B (see --help)");
  geom = numbers(text.substr(0, colon));
  const auto c = numbers(text.substr(colon + 1));
  if (geom.size() != n_geom || (c.size() != 3 && c.size() != 1))
    throw InputError(flag + " '" + text + "': expected " + std::to_string(n_geom) +
                     " numbers, a colon and 1 or 3 colour values");
  rgb = c.size() == 3 ? Eigen::Vector3d(c[0], c[1], c[2]) : Eigen::Vector3d::Constant(c[0]);
  if (!(rgb.minCoeff() >= 0) || !rgb.allFinite())
    throw InputError(flag + " '" + text + "': colour values must be finite and >= 0");
}

}  // namespace

RenderLights make_lights(const RenderLightFlags& a, PreviewScene scene) {
  RenderLights l;
  l.envmap_path = a.envmap;
  l.envmap_scale = a.env_scale;
  l.envmap_rotation_rad = parse_angle(a.env_rotation);
  l.uniform_white_env = a.white_env;
  std::vector<double> g;
  Eigen::Vector3d c;
  for (const auto& s : a.points) {
    parse_light("--point", s, 3, g, c);
    l.points.push_back({Eigen::Vector3d(g[0], g[1], g[2]), c});
  }
  for (const auto& s : a.sphere_lights) {
    parse_light("--sphere-light", s, 4, g, c);
    if (!(g[3] > 0)) throw InputError("--sphere-light: the radius must be > 0");
    l.spheres.push_back({Eigen::Vector3d(g[0], g[1], g[2]), g[3], c});
  }
  for (const auto& s : a.disk_lights) {
    parse_light("--disk-light", s, 7, g, c);
    if (!(g[6] > 0)) throw InputError("--disk-light: the radius must be > 0");
    l.disks.push_back(
        {Eigen::Vector3d(g[0], g[1], g[2]), Eigen::Vector3d(g[3], g[4], g[5]), g[6], c});
  }
  add_default_light_if_none(l, scene);
  return l;
}

void add_render_light_flags(CLI::App* c, RenderLightFlags& a) {
  c->add_option("--envmap", a.envmap, "Equirectangular environment map (.exr or .hdr)");
  c->add_option("--env-scale", a.env_scale, "Multiplies the environment map")
      ->capture_default_str()
      ->check(positive_number(1e6));
  c->add_option("--env-rotation", a.env_rotation, "Turns the map about the up axis (deg)")
      ->capture_default_str()
      ->check(direction());
  c->add_flag("--white-env", a.white_env, "Uniform white environment of radiance 1");
  c->add_option("--point", a.points, "Point light X,Y,Z:R,G,B (repeatable)");
  c->add_option("--sphere-light", a.sphere_lights, "Sphere light X,Y,Z,RADIUS:R,G,B");
  c->add_option("--disk-light", a.disk_lights, "Disk light X,Y,Z,NX,NY,NZ,RADIUS:R,G,B");
}

}  // namespace microbrdf::cli
