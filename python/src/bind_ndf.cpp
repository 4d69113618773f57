// TabulatedNdf (buffer protocol: np.asarray(D) is a view) and the NDF estimators: naive,
// filtered (Dong 2015 section 5.1) and Kirchhoff D_K (section 6), for one scan or a scan set.
#include <pybind11/stl.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "bindings.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/filter_sigma_auto.hpp"
#include "microbrdf/kirchhoff.hpp"
#include "microbrdf/memory_budget.hpp"
#include "microbrdf/microfacet.hpp"
#include "microbrdf/ndf_convolve.hpp"
#include "microbrdf/ndf_estimate.hpp"
#include "microbrdf/ndf_io.hpp"
#include "microbrdf/ndf_model.hpp"
#include "microbrdf/ndf_preview.hpp"

namespace microbrdf::python {
namespace {

py::dict metadata_dict(const NdfMetadata& m) {
  py::dict d;
  d["method"] = text(m.method);
  d["filter_sigma_m"] = m.filter_sigma_m;
  d["wavelength_m"] = m.wavelength_m;
  py::list sources;
  for (const auto& s : m.sources) sources.append(path_text(s));
  d["sources"] = sources;
  d["samples_used"] = m.samples_used;
  d["samples_skipped"] = m.samples_skipped;
  d["projected_area_m2"] = m.projected_area_m2;
  d["leveling"] = text(m.leveling);
  d["parameterisation"] = text(m.parameterisation);
  d["notes"] = text(m.notes);
  d["sampling"] = ndf_sampling(m);
  d["sampling_recorded"] = ndf_sampling_recorded(m);
  d["window_mass"] = m.window_mass;
  return d;
}

py::array vec(const Eigen::Vector3d& v) {
  py::array_t<double> a(3);
  for (int i = 0; i < 3; ++i) a.mutable_data()[i] = v[i];
  return a;
}

/// The moments `ndf --json` reports, same key names.
py::dict moments(const TabulatedNdf& d) {
  py::dict out;
  out["integral"] = d.integral();
  out["mean_normal"] = vec(d.mean_normal());
  out["peak"] = vec(d.peak());
  const Eigen::Matrix2d c = d.slope_covariance();
  py::array_t<double> cov({2, 2});
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) cov.mutable_at(i, j) = c(i, j);
  out["slope_covariance"] = cov;
  const double sx = d.rms_slope(0), sy = d.rms_slope(M_PI / 2);
  out["slope_rms_x"] = sx;
  out["slope_rms_y"] = sy;
  out["beckmann_alpha_x"] = std::sqrt(2.0) * sx;
  out["beckmann_alpha_y"] = std::sqrt(2.0) * sy;
  return out;
}

/// N of an N x N table, and `tables` such tables (with the estimator's own buffers) within the
/// memory budget.
void check_resolution(std::size_t n, std::uint64_t tables = 4) {
  if (n < 17 || n > 8193) throw InputError("resolution must be in 17..8193");
  check_count("resolution", mul_sat(n, n), 8 * tables, "the NDF tables");
}

TabulatedNdf geometric_ndf(const ScanInputs& in, const NdfEstimateOptions& o,
                           const ReadOptions& read, const LevelingSpec& level,
                           const std::function<void(double)>& hook) {
  NdfAccumulator acc(o);
  for (std::size_t i = 0; i < in.size(); ++i) {
    hook(double(i) / double(in.size()));
    Surface keep;
    acc.add(load_scan(in, i, read, level, keep));
  }
  hook(1.0);
  return acc.result();
}

/// Frees D_K's kept buffers when a binding that computed D_K returns (or throws): a Python
/// session holds on to its process, and those buffers are 100 MB and more.
struct ReleaseKirchhoffBuffers {
  ~ReleaseKirchhoffBuffers() { kirchhoff_release_buffers(); }
};

std::vector<TabulatedNdf> kirchhoff_ndf(const ScanInputs& in, KirchhoffOptions o,
                                        const ReadOptions& read, const LevelingSpec& level,
                                        const std::function<void(double)>& hook) {
  const ReleaseKirchhoffBuffers release;
  std::size_t scan = 0;
  o.progress = [&](double f) { hook((double(scan) + f) / double(in.size())); };
  KirchhoffAccumulator acc(o);
  for (std::size_t i = 0; i < in.size(); ++i) {
    scan = i;
    Surface keep;
    acc.add(load_scan(in, i, read, level, keep));
  }
  return acc.stack_result();
}

/// --filter-sigma auto (filter_sigma_auto.hpp): the sweep's result as a dict, with its tables.
py::dict filter_sigma_auto(const py::object& scans, double wavelength, const py::object& patch,
                           const std::string& window, double accuracy, bool keep_aliases,
                           std::size_t resolution, const std::string& level,
                           const py::object& spacing, double min_support) {
  check_resolution(resolution, 16);  // the sweep keeps a table per sigma tried
  FilterSigmaAutoOptions o;
  o.resolution = resolution;
  o.min_support = min_support;
  o.kirchhoff.wavelength_q = wavelength;
  if (patch.is_none()) {
    o.kirchhoff.patch_x = o.kirchhoff.patch_y = 0;
  } else {
    const auto p = length_pair(patch, "patch");
    o.kirchhoff.patch_x = p->first;
    o.kirchhoff.patch_y = p->second;
  }
  o.kirchhoff.window = parse_kirchhoff_window(window);
  o.kirchhoff.accuracy = accuracy;
  o.kirchhoff.nyquist_mask = !keep_aliases;
  if (!(wavelength > 0)) throw InputError("wavelength must be > 0 (metres)");
  if (!(accuracy > 0 && accuracy < 1)) throw InputError("accuracy must be in (0, 1)");
  const auto lev = LevelingSpec::parse(level);
  const ReadOptions read = read_options(spacing);
  const ScanInputs in = scan_inputs(scans);
  const FilterSigmaAuto r = call_released([&] {
    const ReleaseKirchhoffBuffers release;
    return choose_filter_sigma(
        [&](const std::function<void(const Surface&)>& f) {
          for (std::size_t i = 0; i < in.size(); ++i) {
            Surface keep;
            f(load_scan(in, i, read, lev, keep));
          }
        },
        o);
  });
  py::dict d = json_to_py(r.to_json());
  d["naive"] = std::make_shared<TabulatedNdf>(r.naive);
  d["filtered"] = std::make_shared<TabulatedNdf>(r.filtered);
  d["kirchhoff"] = std::make_shared<TabulatedNdf>(r.kirchhoff);
  return d;
}

py::object ndf(const py::object& scans, const std::string& method, double filter_sigma,
               std::size_t resolution, const std::string& level, const py::object& spacing,
               double min_support, double instrument_fwhm, double wavelength,
               const py::object& patch, const std::string& window, double accuracy, bool direct,
               bool keep_aliases, const py::object& progress, const std::string& integration,
               std::size_t supersample, const std::string& stack) {
  check_resolution(resolution);
  const auto lev = LevelingSpec::parse(level);
  const ReadOptions read = read_options(spacing);
  const auto hook = progress_hook<double>(progress);
  if (method == "kirchhoff") {
    KirchhoffOptions o;
    o.wavelength_q = wavelength;
    o.resolution = resolution;
    if (patch.is_none()) {
      o.patch_x = o.patch_y = 0;
    } else {
      auto p = length_pair(patch, "patch");
      o.patch_x = p->first;
      o.patch_y = p->second;
    }
    o.window = parse_kirchhoff_window(window);
    o.accuracy = accuracy;
    o.direct = direct;
    o.nyquist_mask = !keep_aliases;
    o.integration = parse_kirchhoff_integration(integration);
    o.supersample = supersample;
    if (!(o.wavelength_q > 0)) throw InputError("wavelength must be > 0 (metres)");
    o.stack_wavelengths_q = kirchhoff_stack_layers(stack, o.wavelength_q);
    if (!(o.accuracy > 0 && o.accuracy < 1)) throw InputError("accuracy must be in (0, 1)");
    const ScanInputs in = scan_inputs(scans);
    auto layers = call_released([&] { return kirchhoff_ndf(in, o, read, lev, hook); });
    if (layers.size() == 1) return py::cast(std::make_shared<TabulatedNdf>(std::move(layers[0])));
    py::list out;
    for (auto& t : layers) out.append(std::make_shared<TabulatedNdf>(std::move(t)));
    return out;
  }
  NdfEstimateOptions o;
  if (method == "naive")
    o.method = NdfMethod::Naive;
  else if (method == "filtered")
    o.method = NdfMethod::Filtered;
  else
    throw InputError("unknown method '" + method + "' (naive | filtered | kirchhoff)");
  if (!(filter_sigma > 0) || !std::isfinite(filter_sigma))
    throw InputError("filter_sigma must be positive (metres)");
  if (!(instrument_fwhm >= 0)) throw InputError("instrument_fwhm must be >= 0 (radians)");
  o.filter_sigma_m = filter_sigma;
  o.resolution = resolution;
  o.min_support = min_support;
  const ScanInputs in = scan_inputs(scans);
  return py::cast(call_released([&] {
    TabulatedNdf d = geometric_ndf(in, o, read, lev, hook);
    if (instrument_fwhm > 0) {
      d = convolve_angular_gaussian(d, instrument_fwhm);
      char note[96];
      std::snprintf(note, sizeof note, "convolved with an angular Gaussian of FWHM %.4g deg",
                    instrument_fwhm * 180 / M_PI);
      d.meta.notes = note;
    }
    return std::make_shared<TabulatedNdf>(std::move(d));
  }));
}

}  // namespace

void bind_ndf(py::module_& m) {
  py::class_<TabulatedNdf, std::shared_ptr<TabulatedNdf>> c(
      m, "TabulatedNdf", py::buffer_protocol(),
      R"(A normal distribution function tabulated on the projected unit disk.

N x N nodes, node-centred: m_x = -1 + 2 ix/(N-1), m_y = -1 + 2 iy/(N-1) (row iy, column ix);
a zoomed table covers only its `window` (m_x = x0 + (x1 - x0) ix/(N-1)). Values D(m) per
steradian, 0 outside the unit disk (and the window), normalised so that the integral of
D(m)(m.n) over the hemisphere is 1 (sum D Delta^2 = 1, Delta = 2/(N-1)).

np.asarray(D) and D.values are float64 (N, N) views of the table (no copy), writable; they
keep the table alive.

TabulatedNdf(values): a table from an (N, N) array (copied once; not normalised).)");
  c.def(py::init([](const py::object& values) {
          CArray a = CArray::ensure(values);
          if (!a || a.ndim() != 2 || a.shape(0) != a.shape(1) || a.shape(0) < 3)
            throw py::value_error("TabulatedNdf: values must be a square (N, N) array, N >= 3");
          auto d = std::make_shared<TabulatedNdf>(std::size_t(a.shape(0)));
          std::copy(a.data(), a.data() + a.size(), d->values().begin());
          return d;
        }),
        py::arg("values"))
      .def_buffer([](TabulatedNdf& d) {
        const py::ssize_t n = py::ssize_t(d.resolution());
        return py::buffer_info(d.values().data(), {n, n},
                               {n * py::ssize_t(sizeof(double)), py::ssize_t(sizeof(double))});
      })
      .def_property_readonly(
          "values",
          [](py::object self) {
            auto& d = self.cast<TabulatedNdf&>();
            const py::ssize_t n = py::ssize_t(d.resolution());
            return view(d.values().data(), {n, n}, self);
          },
          "The table, float64 (N, N), 1/sr: a writable view (no copy).")
      .def_property_readonly("resolution", &TabulatedNdf::resolution, "N, nodes per side.")
      .def_property_readonly("spacing", &TabulatedNdf::spacing,
                             "Node spacing Delta = 2 half/(N-1) in disk coordinates (2/(N-1) "
                             "for the whole disk).")
      .def_property_readonly(
          "window",
          [](const TabulatedNdf& d) {
            const NdfWindow& w = d.window();
            py::dict out;
            out["x"] = py::make_tuple(w.x0(), w.x1());
            out["y"] = py::make_tuple(w.y0(), w.y1());
            return out;
          },
          "The square of the disk plane the nodes cover: {'x': (x0, x1), 'y': (y0, y1)}; "
          "(-1, 1) both for the whole disk, smaller for a zoomed table (D = 0 outside it).")
      .def_property_readonly(
          "sampling", [](const TabulatedNdf& d) { return ndf_sampling(d.meta); },
          "'point' (D at the nodes: analytic models, Kirchhoff, measured) or 'cell' (D averaged "
          "over each node's tent cell: histograms of normals); inferred from the method for "
          "files that do not record it (metadata['sampling_recorded'] is then False).")
      .def_property_readonly(
          "nodes",
          [](const TabulatedNdf& d) {
            py::array_t<double> x(static_cast<py::ssize_t>(d.resolution()));
            for (std::size_t i = 0; i < d.resolution(); ++i) x.mutable_data()[i] = d.node_x(i);
            return x;
          },
          "Node coordinates along x: x0 + (x1 - x0) i/(N-1) (-1 + 2 i/(N-1) for the whole disk).")
      .def_property_readonly(
          "nodes_y",
          [](const TabulatedNdf& d) {
            py::array_t<double> y(static_cast<py::ssize_t>(d.resolution()));
            for (std::size_t i = 0; i < d.resolution(); ++i) y.mutable_data()[i] = d.node_y(i);
            return y;
          },
          "Node coordinates along y (rows): y0 + (y1 - y0) i/(N-1).")
      .def_property_readonly(
          "metadata", [](const TabulatedNdf& d) { return metadata_dict(d.meta); },
          "Where the table came from: method, filter_sigma_m, wavelength_m, "
          "sources, samples_used, samples_skipped, leveling, notes, sampling ('point' | 'cell'), "
          "sampling_recorded, window_mass (share of the normals inside a zoomed window).")
      .def(
          "eval",
          [](const TabulatedNdf& d, const py::object& m_obj) {
            const Vec3Array mv = vec3_array(m_obj, "m");
            py::array_t<double> out(static_cast<py::ssize_t>(mv.n));
            double* o = out.mutable_data();
            {
              py::gil_scoped_release r;
              for (std::size_t i = 0; i < mv.n; ++i) o[i] = d.eval(mv[i]);
            }
            if (mv.single) return py::object(py::float_(o[0]));
            return py::object(out);
          },
          py::arg("m"),
          "D(m) per steradian (bilinear), m: (N, 3) or (3,) directions (need not be unit).")
      .def("integral", &TabulatedNdf::integral,
           "sum D Delta^2 = integral of D(m)(m.n) dw (1 for a normalised table).")
      .def("normalise", &TabulatedNdf::normalise, "Scales the table in place to integral 1.")
      .def("moments", &moments,
           "Dict: integral, mean_normal (unit 3-vector), peak (unit 3-vector), slope_covariance "
           "(2x2, of the slopes -m_x/m_z, -m_y/m_z), slope_rms_x, slope_rms_y, "
           "beckmann_alpha_x, beckmann_alpha_y (sqrt(2) x rms slope); the keys of `ndf --json`.")
      .def("rms_slope", &TabulatedNdf::rms_slope, py::arg("azimuth"),
           "rms slope along the in-plane direction at `azimuth` (rad), about the mean.")
      .def(
          "slice",
          [](const TabulatedNdf& d, double azimuth, std::size_t samples) {
            if (samples < 2) throw InputError("slice: samples must be >= 2");
            check_count("samples", samples, 6 * sizeof(double), "the slice's arrays");
            NdfSlice s = d.slice(azimuth, samples);
            py::dict out;
            out["t"] = py::array_t<double>(py::ssize_t(s.t.size()), s.t.data());
            out["theta"] = py::array_t<double>(py::ssize_t(s.theta.size()), s.theta.data());
            out["value"] = py::array_t<double>(py::ssize_t(s.value.size()), s.value.data());
            return out;
          },
          py::arg("azimuth") = 0.0, py::arg("samples") = 1025,
          "Cut through the disk centre at `azimuth` (rad): dict of arrays t (signed disk "
          "coordinate), theta (signed polar angle of m, rad), value (D, 1/sr).")
      .def(
          "resampled",
          [](const TabulatedNdf& d, std::size_t resolution) {
            if (resolution < 3) throw InputError("resolution must be >= 3");
            check_count("resolution", mul_sat(resolution, resolution), sizeof(double),
                        "the resampled table");
            return call_released([&] { return d.resampled(resolution); });
          },
          py::arg("resolution"),
          "Bilinear resampling to another resolution (same window; normalised again).")
      .def(
          "save",
          [](const TabulatedNdf& d, const py::object& path) {
            const std::string p = fspath(path, "path");
            call_released([&] { write_ndf(d, p); });
          },
          py::arg("path"),
          "Writes the table: .npy (float64 N x N, + a .json sidecar with the metadata) or .exr; "
          "what `microbrdf ndf -o` writes. Atomic.")
      .def(
          "save_preview",
          [](const TabulatedNdf& d, const py::object& path, bool zoom) {
            const std::string p = fspath(path, "path");
            NdfPreviewOptions po;
            po.zoom = zoom;
            call_released([&] { write_ndf_preview(d, p, po); });
          },
          py::arg("path"), py::arg("zoom") = false,
          "Log-scale false-colour PNG of the disk (the CLI's --preview).")
      .def("__repr__", [](const TabulatedNdf& d) {
        return text("<microbrdf.TabulatedNdf " + d.meta.method + " " +
                    std::to_string(d.resolution()) + " x " + std::to_string(d.resolution()) + ">");
      });

  m.def(
      "read_ndf",
      [](const py::object& path) {
        const std::string p = fspath(path, "path");
        return call_released([&] { return std::make_shared<TabulatedNdf>(read_ndf(p)); });
      },
      py::arg("path"),
      "Reads a table written by `microbrdf ndf` or TabulatedNdf.save (.npy/.exr).");

  m.def("ndf", &ndf, py::arg("surface"), py::arg("method") = "filtered",
        py::arg("filter_sigma") = 1e-6, py::arg("resolution") = 1025, py::arg("level") = "plane",
        py::arg("spacing") = py::none(), py::arg("min_support") = 0.5,
        py::arg("instrument_fwhm") = 0.0, py::arg("wavelength") = 555e-9,
        py::arg("patch") = py::make_tuple(70e-6, 53e-6), py::arg("window") = "hann",
        py::arg("accuracy") = KirchhoffOptions{}.accuracy, py::arg("direct") = false,
        py::arg("keep_aliases") = false, py::arg("progress") = py::none(),
        py::arg("integration") = "midpoint", py::arg("supersample") = 0,
        py::arg("stack") = "visible",
        R"(The normal distribution function of one scan or of a scan set, as `microbrdf ndf`.

surface: a Surface, a path (or glob, directory, @manifest), or a list of them; several scans
    are estimated one by one and averaged (by projected area; D_K by patch intensity).
method: 'naive' (two triangles per grid cell), 'filtered' (normal of the plane fitted with a
    Gaussian of std filter_sigma at each sample; Dong 2015 sec. 5.1) or 'kirchhoff' (the
    Kirchhoff distribution D_K at lambda_q = wavelength; Dong eq. 6, App. A).
filter_sigma: metres (filtered). resolution: N of the N x N table (17..8193).
level: levelling of every scan first: 'none' | 'plane' | 'poly2'..'poly6' (on a copy of a
    Surface). spacing: dx or (dx, dy), metres, for files that do not store it.
min_support: filtered: minimum weighted support, fraction of the full kernel.
instrument_fwhm: naive/filtered: convolve with an angular Gaussian of this FWHM (radians).
wavelength: kirchhoff: lambda_q, metres. patch: kirchhoff: tile size (dx, dy) in metres, or
    None for one tile per scan. window: 'hann' (default) | 'gauss' | 'none'. accuracy: tail bound of the
    fast method. direct: direct sums (slow reference). keep_aliases: keep nodes beyond the
    scan's Nyquist band.
progress: optional callable(fraction in [0, 1]), called from the calling thread.
integration: kirchhoff: 'midpoint' (the midpoint rule per sample; the default, as in the CLI)
    or 'exact' (exactly over the triangles of the piecewise-linear surface: the reference,
    20-60x slower; right for truly faceted surfaces, while on sampled band-limited data its
    power falls as sinc^4(q d/2)). supersample: kirchhoff: node values as
    cell averages over S x S sub-nodes (S odd, 1..15); 0 chooses S from the tile size and
    lambda_q (the CLI's --dk-supersample auto), 1 takes point samples.

stack: kirchhoff: 'visible' (default: tables over lambda_q from 360 nm to 6 x 830 nm and at
    wavelength, for brdf(kirchhoff=...) to interpolate at each direction's lambda_q),
    'wavelength' (over wavelength .. 6 x wavelength) or 'single' (one table).

Runs without the GIL; Ctrl-C interrupts it (between scans, and between Kirchhoff patches).
Returns a TabulatedNdf equal bit for bit to what the CLI writes for the same inputs and flags;
for a D_K stack, a list of TabulatedNdf sorted by lambda_q (metadata['wavelength_m']), the
layers of the CLI's 3-D .npy.)");

  m.def("hellinger_distance", &hellinger_distance, py::arg("a"), py::arg("b"),
        "Hellinger distance between two tables of the same resolution, in [0, 1]: H^2 = 1 - "
        "sum sqrt(p q) over the nodes, p and q the nodes' probabilities under D(m)(m.n) dw.");
  m.def(
      "filter_sigma_auto", &filter_sigma_auto, py::arg("surface"), py::arg("wavelength") = 555e-9,
      py::arg("patch") = py::make_tuple(70e-6, 53e-6), py::arg("window") = "hann",
      py::arg("accuracy") = KirchhoffOptions{}.accuracy, py::arg("keep_aliases") = false,
      py::arg("resolution") = 257, py::arg("level") = "plane", py::arg("spacing") = py::none(),
      py::arg("min_support") = 0.5,
      R"(The filter sigma whose filtered NDF is nearest D_K, as `microbrdf ndf --filter-sigma auto`.

surface: as for ndf(). wavelength, patch, window, accuracy, keep_aliases: the D_K compared with
(as for ndf(method='kirchhoff')). resolution: N of the sweep's tables. level, spacing,
min_support: as for ndf().

Returns a dict: sigma_m (the chosen sigma), hellinger (its distance to D_K), curve (a list of
{sigma_m, hellinger}, ascending), sweep (range, points, resolution, wavelength_q_m,
kirchhoff_raw_integral, kirchhoff_aliased_fraction, at_lower_end, at_upper_end), distances
(naive_kirchhoff, naive_filtered, filtered_kirchhoff), and the tables naive, filtered (at the
chosen sigma) and kirchhoff at the sweep's resolution.)");

  m.def(
      "ndf_models",
      [] {
        nlohmann::json out = nlohmann::json::array();
        for (const NdfModel* mo : ndf_models()) {
          nlohmann::json ps = nlohmann::json::array();
          for (const auto& p : mo->params())
            ps.push_back(
                {{"name", p.name}, {"unit", p.unit}, {"help", p.help}, {"default", p.def}});
          out.push_back({{"name", mo->name()},
                         {"aliases", mo->aliases()},
                         {"summary", mo->summary()},
                         {"params", ps}});
        }
        return json_to_py(out);
      },
      "The registered NDF models: a list of dicts {name, aliases, summary, params: [{name, unit, "
      "help, default}]}; tabulate, brdf and fit take these names and parameters ('mixture:A+B' "
      "in fit).");

  m.def(
      "tabulate",
      [](const std::string& model, double alpha_x, double alpha_y, double phi, double theta_x,
         double theta_y, double theta_z, std::size_t resolution, const py::object& window,
         const py::kwargs& extra) {
        check_resolution(resolution, 1);
        NdfWindow w;
        if (!window.is_none()) {
          const auto v = window.cast<std::vector<double>>();
          if (v.size() != 3 || !(v[2] > 0 && v[2] <= 1) || !(std::abs(v[0]) + v[2] <= 1) ||
              !(std::abs(v[1]) + v[2] <= 1))
            throw InputError(
                "window must be (cx, cy, half) with the square inside [-1, 1]^2 (0 < half <= 1)");
          w = zoom_window(v[0], v[1], v[2]);
        }
        NdfSpec s;
        s.model = model;
        s.alpha_x = alpha_x;
        s.alpha_y = alpha_y > 0 ? alpha_y : alpha_x;
        s.phi = phi;
        s.theta_x = theta_x;
        s.theta_y = theta_y;
        s.theta_z = theta_z;
        // The other parameters of the registered models (e.g. gamma=), by name.
        for (const auto& [k, v] : extra) s.extra[k.cast<std::string>()] = v.cast<double>();
        auto d = make_distribution(s);
        return std::make_shared<TabulatedNdf>(tabulate(*d, model, resolution, w));
      },
      py::arg("model") = "ggx", py::arg("alpha_x") = 0.1, py::arg("alpha_y") = 0.0,
      py::arg("phi") = 0.0, py::arg("theta_x") = 0.0, py::arg("theta_y") = 0.0,
      py::arg("theta_z") = 0.0, py::arg("resolution") = 1025, py::arg("window") = py::none(),
      "A parametric NDF (any registered model: ndf_models(); 'beckmann' | 'ggx' | 'ellipsoid' | "
      "...) written into a table, as `microbrdf tabulate`. alpha_y = 0 means alpha_y = alpha_x; "
      "angles in radians; the models' other parameters as keywords (e.g. gamma=). "
      "window=(cx, cy, half): a zoomed table of that square of the disk plane (`tabulate "
      "--window`). The table records sampling 'point'.");
}

}  // namespace microbrdf::python
