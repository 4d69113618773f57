// The JSON micro-scene format (docs/westin.md, "Micro-scenes"; examples/scenes/*.json).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "microbrdf/brdf.hpp"
#include "microbrdf/brdf_spec.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/generate.hpp"
#include "microbrdf/io.hpp"
#include "microbrdf/json_read.hpp"
#include "microbrdf/material_spec.hpp"
#include "microbrdf/memory_budget.hpp"
#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/microscene.hpp"
#include "microbrdf/sh_brdf.hpp"
#include "microbrdf/units.hpp"

namespace microbrdf {
namespace {

using nlohmann::json;

struct Ctx {
  std::string origin;    // file name for messages
  std::string base_dir;  // for relative paths
  [[noreturn]] void fail(const std::string& what) const { throw FileError(origin, what); }
  std::string path(const std::string& p) const {
    if (p.empty() || std::filesystem::path(p).is_absolute()) return p;
    return (std::filesystem::path(base_dir) / p).string();
  }
};

// The string v (the value of `key`) read by `parse` (a quantity with a unit); its error names
// the key and the file.
template <class Parse>
double parsed(const Ctx& c, const json& v, const char* key, Parse parse) {
  try {
    return parse(v.get<std::string>());
  } catch (const InputError& e) {
    c.fail(std::string("'") + key + "': " + e.what());
  }
}

double length(const Ctx& c, const json& o, const char* key, std::optional<double> def = {}) {
  if (!o.contains(key)) {
    if (def) return *def;
    c.fail(std::string("missing length '") + key + "'");
  }
  const json& v = o.at(key);
  if (!v.is_string())
    c.fail(std::string("'") + key + "' must be a length with a unit, e.g. \"10um\"");
  return parsed(c, v, key, parse_length);
}

double angle(const Ctx& c, const json& o, const char* key, double def) {
  if (!o.contains(key)) return def;
  const json& v = o.at(key);
  if (v.is_number()) return v.get<double>() * M_PI / 180;
  if (!v.is_string()) c.fail(std::string("'") + key + "' must be an angle (\"30deg\" or 30)");
  return parsed(c, v, key, parse_angle);
}

double number(const Ctx& c, const json& o, const char* key, double def) {
  if (!o.contains(key)) return def;
  if (!o.at(key).is_number()) c.fail(std::string("'") + key + "' must be a number");
  return o.at(key).get<double>();
}

int integer(const Ctx& c, const json& o, const char* key, int def) {
  if (!o.contains(key)) return def;
  if (!o.at(key).is_number_integer()) c.fail(std::string("'") + key + "' must be an integer");
  const json& v = o.at(key);
  // Read as 64-bit and range-checked: 4294967304 must not become 8.
  if (v.is_number_unsigned()
          ? v.get<std::uint64_t>() > std::uint64_t(INT32_MAX)
          : (v.get<std::int64_t>() > INT32_MAX || v.get<std::int64_t>() < INT32_MIN))
    c.fail(std::string("'") + key + "' is out of range (" + v.dump() + ")");
  return v.get<int>();
}

// A count of objects or samples: an integer in [lo, hi], read as 64-bit.
std::int64_t count(const Ctx& c, const json& o, const char* key, std::int64_t def, std::int64_t lo,
                   std::int64_t hi) {
  if (!o.contains(key)) return def;
  const json& v = o.at(key);
  if (!v.is_number_integer()) c.fail(std::string("'") + key + "' must be an integer");
  const bool big = v.is_number_unsigned() && v.get<std::uint64_t>() > std::uint64_t(INT64_MAX);
  const std::int64_t n = big ? INT64_MAX : v.get<std::int64_t>();
  if (big || n < lo || n > hi)
    c.fail(std::string("'") + key + "' is " + v.dump() + "; it must lie in " + std::to_string(lo) +
           ".." + std::to_string(hi));
  return n;
}

std::string text(const Ctx& c, const json& o, const char* key, const std::string& def) {
  if (!o.contains(key)) return def;
  if (!o.at(key).is_string()) c.fail(std::string("'") + key + "' must be a string");
  return o.at(key).get<std::string>();
}

// The reflectance of a mirror or microfacet material: the keys of the material vocabulary
// (material_spec.hpp: metal, n + k, nk_csv, r0, color, fresnel) or "eta" (a dielectric's
// reflectance); with none, R = 1 (null). A relative nk_csv path is relative to the scene file.
std::shared_ptr<const Fresnel> surface_fresnel(const Ctx& c, const std::string& name,
                                               const json& m) {
  try {
    MaterialSpec spec;
    spec.form = MaterialSpec::Form::Perfect;
    if (m.contains("eta") && !has_material(m)) {
      spec.form = MaterialSpec::Form::Dielectric;
      spec.eta = number(c, m, "eta", 1.5);
    } else {
      spec = parse_material(m, spec, KeyStyle::Json);
    }
    if (spec.form == MaterialSpec::Form::Perfect) return nullptr;
    if (spec.form == MaterialSpec::Form::NkCsv) spec.nk_csv = c.path(spec.nk_csv);
    return make_fresnel(spec);
  } catch (const InputError& e) {
    c.fail("material '" + name + "': " + e.what() +
           " (the reflectance is given by \"metal\", \"n\" + \"k\", \"nk_csv\", \"r0\", "
           "\"color\" or \"eta\", with \"fresnel\": \"exact\" or \"schlick\")");
  }
}

MicroMaterial material(const Ctx& c, const std::string& name, const json& m) {
  if (!m.is_object()) c.fail("material '" + name + "' must be an object");
  MicroMaterial out;
  out.name = name;
  const std::string type = text(c, m, "type", "");
  if (type == "mirror") {
    out.kind = MicroMaterial::Kind::Mirror;
    out.fresnel = surface_fresnel(c, name, m);
  } else if (type == "dielectric") {
    out.kind = MicroMaterial::Kind::Dielectric;
    out.eta = number(c, m, "eta", 1.5);
    if (!(out.eta > 0)) c.fail("material '" + name + "': eta must be > 0");
    out.absorption = m.contains("absorption") ? 1 / length(c, m, "absorption") : 0;
    // "absorption" is the Beer length 1/kappa (e.g. "2mm"); "absorption_per_m" the coefficient.
    if (m.contains("absorption_per_m")) out.absorption = number(c, m, "absorption_per_m", 0);
  } else if (type == "lambert") {
    out.kind = MicroMaterial::Kind::Lambert;
    out.albedo = number(c, m, "albedo", 1.0);
    if (!(out.albedo >= 0 && out.albedo <= 1))
      c.fail("material '" + name + "': albedo must be in [0, 1]");
  } else if (type == "microfacet") {
    out.kind = MicroMaterial::Kind::Brdf;
    // The BRDF vocabulary's analytic model (brdf_spec.hpp; default beckmann, alpha 0.1).
    if (m.contains("distribution")) c.fail("material '" + name + "': the NDF is \"model\"");
    json keys = m;
    if (!keys.contains("model")) keys["model"] = "beckmann";
    if (!keys.contains("alpha") && !keys.contains("alpha_x")) keys["alpha"] = 0.1;
    std::shared_ptr<const Fresnel> f = surface_fresnel(c, name, m);
    if (!f) f = std::make_shared<PerfectMirrorFresnel>();
    try {
      const BrdfSpec spec = parse_brdf(keys, std::nullopt, KeyStyle::Json);
      if (spec.kind != BrdfSpec::Kind::Analytic)
        c.fail("material '" + name + "': a microfacet material takes an analytic model");
      out.brdf = make_microfacet_brdf(make_distribution(spec.model), f, spec);
    } catch (const InputError& e) {
      c.fail("material '" + name + "': " + e.what());
    }
    out.uniform_sampling = text(c, m, "sampling", "brdf") == "uniform";
  } else if (type == "shbrdf") {
    out.kind = MicroMaterial::Kind::Brdf;
    const std::string file = text(c, m, "file", "");
    if (file.empty()) c.fail("material '" + name + "': shbrdf needs \"file\"");
    out.brdf = std::make_shared<ShBrdf>(ShBrdf::load(c.path(file)));
    out.uniform_sampling = text(c, m, "sampling", "brdf") == "uniform";
  } else if (type == "absorber") {
    out.kind = MicroMaterial::Kind::Absorber;
  } else {
    c.fail("material '" + name +
           "': type must be mirror, dielectric, lambert, microfacet, shbrdf "
           "or absorber (got '" +
           type + "')");
  }
  return out;
}

Surface heightfield_surface(const Ctx& c, const json& o) {
  Surface s;
  if (o.contains("file")) {
    ReadOptions ro;
    if (o.contains("spacing")) ro.dx = ro.dy = length(c, o, "spacing");
    s = read_surface(c.path(text(c, o, "file", "")), ro);
    // Heights about their mean (the notional plane is z = 0).
    const double mean = s.valid_mean();
    for (double& z : s.z) z -= mean;
  } else if (o.contains("generate")) {
    const json& g = o.at("generate");
    const std::string kind = text(c, g, "kind", "gaussian");
    if (kind == "gaussian") {
      GaussianSurfaceParams p;
      p.nx = static_cast<std::size_t>(count(c, g, "nx", 512, 2, 1 << 15));
      p.ny =
          static_cast<std::size_t>(count(c, g, "ny", static_cast<std::int64_t>(p.nx), 2, 1 << 15));
      check_memory(c.origin, mul_sat(p.nx * p.ny, 64), "a generated height field");
      p.dx = p.dy = length(c, g, "spacing");
      p.sigma = length(c, g, "sigma");
      p.tau_x = length(c, g, "tau");
      p.tau_y = g.contains("tau_y") ? length(c, g, "tau_y") : p.tau_x;
      p.angle = angle(c, g, "angle", 0);
      p.seed = static_cast<std::uint64_t>(integer(c, g, "seed", 1));
      p.exact_spectrum = g.value("exact_spectrum", true);
      s = about_file(c.origin, [&] { return generate_gaussian(p); });
    } else {
      c.fail("heightfield generate.kind must be \"gaussian\" (got '" + kind + "')");
    }
  } else {
    c.fail("heightfield needs \"file\" or \"generate\"");
  }
  const double zs = number(c, o, "z_scale", 1.0);
  if (zs != 1)
    for (double& z : s.z) z *= zs;
  const std::string tiling = text(c, o, "tiling", "periodic");
  if (tiling == "mirror")
    s = mirror_tile(s);
  else if (tiling != "periodic")
    c.fail("heightfield tiling must be \"periodic\" or \"mirror\"");
  s.x0 = s.y0 = 0;
  return s;
}

// Everything but `source`: the callers decide whether the document is copied or moved.
MicroSceneDesc parse_scene_objects(const json& j, const std::string& base_dir,
                                   const std::string& origin) {
  const Ctx c{origin, base_dir};
  if (!j.is_object()) c.fail("a micro-scene is a JSON object");
  MicroSceneDesc d;
  d.name = text(c, j, "name", std::filesystem::path(origin).stem().string());
  d.wavelength_m = j.contains("wavelength") ? length(c, j, "wavelength") : 550e-9;
  d.rotation = angle(c, j, "rotation", 0);
  if (!j.contains("materials") || !j.at("materials").is_object())
    c.fail("missing \"materials\" object");
  for (const auto& [name, m] : j.at("materials").items())
    d.materials.push_back(material(c, name, m));
  if (!j.contains("objects") || !j.at("objects").is_array()) c.fail("missing \"objects\" array");
  const json& objects = j.at("objects");
  auto mat = [&](const json& o, const char* key = "material") {
    try {
      return d.material_index(text(c, o, key, ""));
    } catch (const InputError& e) {
      c.fail(e.what());
    }
  };
  // Height fields first: they may define the tile.
  for (const json& o : objects)
    if (text(c, o, "type", "") == "heightfield")
      d.heightfields.push_back(
          {heightfield_surface(c, o), mat(o), text(c, o, "mesh", "triangles") == "grid"});
  if (j.contains("tile")) {
    try {
      const LengthPair t = parse_length_pair(j.at("tile").get<std::string>());
      d.width = t.x;
      d.height = t.y;
    } catch (const std::exception& e) {
      c.fail(std::string("tile: give \"WxHunit\", e.g. \"1x1mm\": ") + e.what());
    }
  } else if (!d.heightfields.empty()) {
    d.width = d.heightfields[0].surface.width();
    d.height = d.heightfields[0].surface.height();
  } else {
    c.fail("no \"tile\" and no height field to take it from");
  }
  // A tile of zero (or absurd) size has no surface to trace: refused before any object is made.
  if (!(d.width > 0 && d.height > 0 && d.width < 1 && d.height < 1))
    c.fail("tile: both sides must be > 0 and < 1 m (a micro-scene; got " + std::to_string(d.width) +
           " x " + std::to_string(d.height) + " m)");
  try {
    for (const json& o : objects) {
      const std::string type = text(c, o, "type", "");
      if (type == "heightfield") continue;
      if (type == "plane") {
        d.planes.push_back({length(c, o, "z", 0.0), mat(o)});
      } else if (type == "cylinders") {
        const double r = length(c, o, "radius");
        // Along x (angle 0) or y (angle 90 deg); other orientations: the scene's "rotation".
        const double ang = angle(c, o, "angle", 0);
        const bool along_y = std::abs(ang - M_PI / 2) < 1e-9;
        if (!along_y && std::abs(ang) > 1e-9)
          c.fail("cylinders: angle must be 0 or 90 deg (turn the scene with \"rotation\")");
        std::int64_t n_cyl = count(c, o, "count", 8, 1, kMaxSceneObjects);
        if (o.contains("pitch")) {
          const double across = along_y ? d.width : d.height;
          const double n = across / length(c, o, "pitch");
          if (!(n >= 0.5 && n < double(kMaxSceneObjects)))
            c.fail("cylinders: " + std::to_string(n) + " pitches across the tile");
          n_cyl = std::llround(n);
          if (std::abs(n - double(n_cyl)) > 1e-6 * n)
            c.fail("cylinders: the tile must be a whole number of pitches (" + std::to_string(n) +
                   ")");
        }
        add_cylinders(d, r, n_cyl, length(c, o, "z", r), number(c, o, "jitter", 0),
                      integer(c, o, "seed", 1), mat(o), along_y);
      } else if (type == "spheres") {
        const double r = length(c, o, "radius");
        add_spheres(d, r, length(c, o, "pitch"), length(c, o, "z", r), number(c, o, "jitter", 0),
                    integer(c, o, "seed", 1), mat(o));
      } else if (type == "fibers") {
        FiberParams p;
        p.count = count(c, o, "count", p.count, 1, kMaxSceneObjects);
        p.radius = length(c, o, "radius", p.radius);
        p.length = length(c, o, "length", p.length);
        p.tilt = angle(c, o, "tilt", p.tilt);
        p.tilt_spread = angle(c, o, "tilt_spread", p.tilt_spread);
        p.tilt_azimuth = angle(c, o, "tilt_azimuth", p.tilt_azimuth);
        p.azimuth_spread = angle(c, o, "azimuth_spread", p.azimuth_spread);
        p.seed = integer(c, o, "seed", 1);
        p.material = mat(o);
        add_fibers(d, p);
      } else if (type == "weave") {
        WeaveParams p;
        p.pitch = length(c, o, "pitch", p.pitch);
        p.radius = length(c, o, "radius", p.radius);
        p.crimp = length(c, o, "crimp", p.radius);
        p.segments_per_pitch = count(c, o, "segments", p.segments_per_pitch, 2, 4096);
        if (o.contains("material")) p.warp_material = p.weft_material = mat(o);
        if (o.contains("warp_material")) p.warp_material = mat(o, "warp_material");
        if (o.contains("weft_material")) p.weft_material = mat(o, "weft_material");
        add_weave(d, p);
      } else {
        c.fail(
            "object type must be heightfield, plane, cylinders, spheres, fibers or weave (got '" +
            type + "')");
      }
    }
    check_scene_geometry(d);
  } catch (const InputError& e) {
    c.fail(e.what());
  }
  return d;
}

}  // namespace

MicroSceneDesc parse_micro_scene(const json& j, const std::string& base_dir,
                                 const std::string& origin) {
  MicroSceneDesc d = parse_scene_objects(j, base_dir, origin);
  d.source = j;
  return d;
}

MicroSceneDesc load_micro_scene(const std::string& path) {
  json j = read_json_file(path, /*ignore_comments=*/true);
  const auto dir = std::filesystem::path(path).parent_path().string();
  MicroSceneDesc d = parse_scene_objects(j, dir.empty() ? "." : dir, path);
  d.source = std::move(j);  // kept as metadata: moved, never copied
  return d;
}

}  // namespace microbrdf
