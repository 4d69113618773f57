// Surface (height map with numpy views), read_surface, statistics and levelling.
#include <pybind11/stl.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "bindings.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/rayleigh_rice.hpp"
#include "microbrdf/scanset.hpp"
#include "microbrdf/statistics.hpp"

namespace microbrdf::python {
namespace {

std::shared_ptr<Surface> surface_from_array(const py::object& z_obj, const py::object& spacing,
                                            const py::object& mask_obj) {
  CArray z = CArray::ensure(z_obj);
  if (!z || z.ndim() != 2) throw py::value_error("Surface: heights must be a 2-D array (ny, nx)");
  const auto sp = length_pair(spacing, "spacing");
  if (!sp) throw py::value_error("Surface: spacing (metres) is required");
  const std::size_t ny = z.shape(0), nx = z.shape(1);
  if (nx < 1 || ny < 1) throw py::value_error("Surface: empty height map");
  auto s = std::make_shared<Surface>(nx, ny, sp->first, sp->second);
  std::copy(z.data(), z.data() + nx * ny, s->z.begin());
  if (!mask_obj.is_none()) {
    auto mask = py::array_t<bool, py::array::c_style | py::array::forcecast>::ensure(mask_obj);
    if (!mask || mask.ndim() != 2 || std::size_t(mask.shape(0)) != ny ||
        std::size_t(mask.shape(1)) != nx)
      throw py::value_error("Surface: mask must have the shape of the heights");
    for (std::size_t i = 0; i < nx * ny; ++i) s->valid[i] = mask.data()[i] ? 1 : 0;
  }
  s->sync_mask();
  return s;
}

py::dict metadata_dict(const Surface& s) {
  py::dict d;
  const auto& m = s.meta;
  // Instrument files carry text in any encoding (a Latin-1 comment): never UnicodeDecodeError.
  d["source_path"] = path_text(m.source_path);
  d["format"] = text(m.format);
  d["instrument"] = text(m.instrument);
  d["date"] = text(m.date);
  d["comment"] = text(m.comment);
  d["z_unit_in_file"] = text(m.z_unit_in_file);
  d["leveling"] = text(m.leveling);
  for (const auto& [k, v] : m.extra) d[text(k)] = text(v);
  return d;
}

/// The `info --json` record of one surface (with the levelling report, as `info` adds it).
/// Also the PSD record and the material-free TIS table, as `info --json` without a material.
nlohmann::json statistics_record(const std::string& path, const Surface& s, const SurfaceStats& st,
                                 const std::string& leveling_report) {
  nlohmann::json j = stats_json(path, s, st);
  j["leveling_report"] = leveling_report;
  add_psd_and_tis_json(j, s, path, nullptr);
  return j;
}

}  // namespace

ReadOptions read_options(const py::object& spacing) {
  ReadOptions o;
  if (auto sp = length_pair(spacing, "spacing")) {
    o.dx = sp->first;
    o.dy = sp->second;
  }
  return o;
}

ScanInputs scan_inputs(const py::object& obj) {
  ScanInputs in;
  std::vector<py::handle> items;
  if (is_path(obj) || py::isinstance<Surface>(obj)) {
    items.push_back(obj);
  } else if (py::isinstance<py::sequence>(obj)) {
    for (auto item : obj.cast<py::sequence>()) items.push_back(item);
  } else {
    throw py::type_error("expected a Surface, a path, or a list of them");
  }
  if (items.empty()) throw py::value_error("no scans given");
  for (auto item : items) {
    if (py::isinstance<Surface>(item)) {
      in.surfaces.push_back(item.cast<std::shared_ptr<Surface>>());
      in.paths.emplace_back();
    } else if (is_path(item)) {
      // Globs, directories and @manifests expand as on the command line.
      for (auto& p : expand_scan_inputs({fspath(item, "surface")})) {
        in.surfaces.push_back(nullptr);
        in.paths.push_back(p);
      }
    } else {
      throw py::type_error("expected a Surface or a path in the list of scans");
    }
  }
  // Every named file must be there before any is read (a long scan set does not fail late).
  std::vector<std::string> missing;
  std::error_code ec;
  for (const auto& p : in.paths)
    if (!p.empty() && !std::filesystem::exists(p, ec)) missing.push_back(p);
  if (!missing.empty()) {
    std::string others;
    for (std::size_t i = 1; i < missing.size(); ++i) others += (i > 1 ? ", " : "nor ") + missing[i];
    throw FileError::missing(missing[0], others);
  }
  return in;
}

const Surface& load_scan(const ScanInputs& in, std::size_t i, const ReadOptions& read,
                         const LevelingSpec& level, Surface& keep) {
  if (in.surfaces[i]) {
    if (level.mode == Leveling::None) return *in.surfaces[i];
    keep = *in.surfaces[i];
  } else {
    keep = read_surface(in.paths[i], read);
  }
  level_surface(keep, level);
  return keep;
}

void bind_surface(py::module_& m) {
  py::class_<Surface, std::shared_ptr<Surface>> s(m, "Surface", R"(A height map.

Surface(heights, spacing, mask=None)

heights: 2-D array (ny, nx) in metres, row iy = y = iy*dy, column ix = x = ix*dx; NaN or
    +-inf marks an invalid sample. Copied once into the surface (which owns its data).
spacing: dx, or (dx, dy), metres.
mask: optional boolean array of the same shape; False marks a sample invalid.

The attributes `heights` and `valid` are numpy views on the surface's own storage (no copy);
they stay valid while any view or the surface is alive. After writing NaN into `heights`
through the view, call sync_mask().)");
  s.def(py::init(&surface_from_array), py::arg("heights"), py::arg("spacing"),
        py::arg("mask") = py::none())
      .def_property_readonly(
          "heights",
          [](py::object self) {
            auto& su = self.cast<Surface&>();
            return view(su.z.data(), {py::ssize_t(su.ny), py::ssize_t(su.nx)}, self);
          },
          "Heights, metres, shape (ny, nx): a writable view (no copy); NaN = invalid.")
      .def_property_readonly(
          "valid",
          [](py::object self) {
            auto& su = self.cast<Surface&>();
            auto* p = reinterpret_cast<const bool*>(su.valid.data());
            return view(p, {py::ssize_t(su.ny), py::ssize_t(su.nx)}, self, false);
          },
          "Validity mask, shape (ny, nx), bool: a read-only view (no copy).")
      .def_property_readonly(
          "spacing", [](const Surface& su) { return py::make_tuple(su.dx, su.dy); },
          "(dx, dy): sample spacing, metres.")
      .def_property_readonly(
          "shape", [](const Surface& su) { return py::make_tuple(su.ny, su.nx); },
          "(ny, nx): rows, samples per row.")
      .def_readonly("nx", &Surface::nx, "Samples per row (x).")
      .def_readonly("ny", &Surface::ny, "Rows (y).")
      .def_readonly("x0", &Surface::x0, "x of column 0, metres.")
      .def_readonly("y0", &Surface::y0, "y of row 0, metres.")
      .def_readonly("z0", &Surface::z0, "Offset removed by levelling, metres.")
      .def_property_readonly("metadata", &metadata_dict,
                             "What the file said: source_path, format, instrument, date, ...")
      .def_property_readonly(
          "path", [](const Surface& su) { return path_text(su.meta.source_path); },
          "The file the surface was read from ('' when made in memory).")
      .def_property_readonly("valid_fraction", &Surface::valid_fraction,
                             "Fraction of valid samples.")
      .def("sync_mask", &Surface::sync_mask,
           "Makes the mask agree with the heights (non-finite = invalid) after editing them.")
      .def(
          "copy", [](const Surface& su) { return std::make_shared<Surface>(su); },
          "An independent copy.")
      .def(
          "level",
          [](const Surface& su, const std::string& mode) {
            auto out = std::make_shared<Surface>(su);
            const auto spec = LevelingSpec::parse(mode);
            level_surface(*out, spec);
            return out;
          },
          py::arg("mode") = "plane",
          "A levelled copy: mode 'none', 'plane' (least-squares plane) or 'poly2'..'poly6' "
          "(2-D polynomial of that total degree), fitted to the valid samples.")
      .def(
          "save",
          [](const Surface& su, const py::object& path) {
            const std::string p = fspath(path, "path");
            call_released([&] { write_surface(su, p); });
          },
          py::arg("path"),
          "Writes the height map (format from the extension: .x3p, .gwy, .npy (+ .json "
          "sidecar), .xyz, .txt). Atomic; FileError on failure.")
      .def("__repr__", [](const Surface& su) {
        return text("<microbrdf.Surface " + std::to_string(su.nx) + " x " + std::to_string(su.ny) +
                    ", spacing " + std::to_string(su.dx * 1e6) + " x " +
                    std::to_string(su.dy * 1e6) + " um" +
                    (su.meta.source_path.empty() ? "" : ", " + su.meta.source_path) + ">");
      });

  m.def(
      "read_surface",
      [](const py::object& path, const py::object& spacing, std::optional<double> z_scale) {
        const std::string p = fspath(path, "path");
        ReadOptions o = read_options(spacing);
        if (z_scale && !(*z_scale > 0 && std::isfinite(*z_scale)))
          throw InputError("z_scale must be > 0 (metres per stored unit)");
        o.z_scale = z_scale;
        return call_released([&] { return std::make_shared<Surface>(read_surface(p, o)); });
      },
      py::arg("path"), py::arg("spacing") = py::none(), py::arg("z_scale") = py::none(),
      R"(Reads a height map as stored (no levelling).

path: .x3p, .dat (MetroPro), .datx, .sur, .plu, .gwy, .xyz, .txt/.asc/.csv, .npy (spacing
    from a same-stem .json sidecar), .exr, .tif.
spacing: dx or (dx, dy) in metres, for formats that do not store it, or to override it.
z_scale: metres per stored unit, for formats that store no height unit (TIFF, EXR, .npy, text
    grids); integer TIFF images without a z_unit in their description need it.
Raises FileError (an OSError naming the file) for a missing, unreadable or corrupt file.)");

  m.def(
      "statistics",
      [](const py::object& scans, const std::string& level, const py::object& spacing) {
        const auto spec = LevelingSpec::parse(level);
        const ScanInputs in = scan_inputs(scans);
        const ReadOptions ro = read_options(spacing);
        py::list out;
        for (std::size_t i = 0; i < in.size(); ++i) {
          Surface keep;
          std::string report;
          SurfaceStats st;
          const Surface* sp = nullptr;
          nlohmann::json record;
          call_released([&] {
            if (!in.surfaces[i])
              keep = read_surface(in.paths[i], ro);
            else if (spec.mode != Leveling::None)
              keep = *in.surfaces[i];
            sp = (in.surfaces[i] && spec.mode == Leveling::None) ? in.surfaces[i].get() : &keep;
            if (sp == &keep)
              report = level_surface(keep, spec).description;
            else
              report = "none";
            st = compute_stats(*sp);
            record = statistics_record(in.paths[i].empty() ? sp->meta.source_path : in.paths[i],
                                       *sp, st, report);
          });
          out.append(json_to_py(record));
        }
        if (in.size() == 1 && (py::isinstance<Surface>(scans) || is_path(scans)) &&
            in.paths.size() == 1)
          return py::object(out[0]);
        return py::object(out);
      },
      py::arg("surface"), py::arg("level") = "plane", py::arg("spacing") = py::none(),
      R"(Surface statistics: a dict with the keys of `microbrdf info --json` (SI units).

surface: a Surface, a path (or glob, directory, @manifest), or a list of them; one input gives
    one dict, several give a list of dicts.
level: 'none' | 'plane' | 'poly2'..'poly6', applied first (on a copy for a Surface).
Keys: nx, ny, dx_m, dy_m, valid_count, valid_fraction, mean_m, min_m, max_m, sq_m (rms height),
sa_m, skewness, kurtosis (3 for Gaussian), slope_rms_x, slope_rms_y (central differences),
corr_length_x_m, corr_length_y_m, corr_length_m (1/e of the normalised ACF; None when longer
than the scan), path, format, invalid_count, leveling, z0_m, ...; psd (the areal PSD's record:
cycles/m, m^4, docs/rayleigh_rice.md) and tis (the Rayleigh factor per wavelength and angle; the
TIS itself with a material: mb.tis).)");
}

}  // namespace microbrdf::python
