// mb.psd, mb.rayleigh_rice, mb.tis: the areal PSD of a scan and the first-order Rayleigh-Rice
// BRDF of a smooth metal (include/microbrdf/psd.hpp, rayleigh_rice.hpp; docs/rayleigh_rice.md).
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "brdf_factory.hpp"
#include "microbrdf/brdf_spec.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/material_spec.hpp"
#include "microbrdf/psd.hpp"
#include "microbrdf/rayleigh_rice.hpp"

namespace microbrdf::python {
namespace {

using PsdPtr = std::shared_ptr<const AreaPsd>;

// A Psd object as it is, or the PSD of one scan (a Surface or a path) levelled as asked.
PsdPtr psd_of(const py::object& surface, const std::string& window, const py::object& tile,
              const std::string& level, const py::object& spacing) {
  if (py::isinstance<AreaPsd>(surface)) return surface.cast<std::shared_ptr<AreaPsd>>();
  // tile: "auto" (default), "whole" or None (one periodogram), or a side in samples.
  std::string tile_text = "whole";
  if (py::isinstance<py::str>(tile))
    tile_text = tile.cast<std::string>();
  else if (!tile.is_none()) {
    const long t = tile.cast<long>();
    if (t < 2) throw InputError("tile must be at least 2 samples, 'auto' or 'whole'");
    tile_text = std::to_string(t);
  }
  const PsdWindow win = parse_psd_window(window);
  const auto lev = LevelingSpec::parse(level);
  const ReadOptions read = read_options(spacing);
  const ScanInputs in = scan_inputs(surface);
  if (in.size() != 1)
    throw InputError("psd: give one scan (got " + std::to_string(in.size()) + ")");
  return call_released([&] {
    Surface keep;
    const Surface& s = load_scan(in, 0, read, lev, keep);
    const std::string name = in.paths[0].empty() ? "surface" : in.paths[0];
    const PsdOptions o = psd_options(s, win, tile_text);  // a bad tile is the caller's error
    return std::make_shared<const AreaPsd>(about_file(name, [&] { return areal_psd(s, o, name); }));
  });
}

// The material keywords (metal=, n=/k=, nk_csv=, r0=, color=) as optical constants; nothing
// when none is given and it is optional.
std::optional<OpticalConstants> material_of(const py::kwargs& kwargs, const std::string& who,
                                            bool required) {
  const nlohmann::json keys = file_spec_keys(kwargs, who);
  for (const auto& k : brdf_keys())
    if (keys.contains(k)) throw InputError(who + ": '" + k + "' is not a material keyword");
  if (keys.contains("fresnel"))
    throw InputError(who + ": the Rayleigh-Rice BRDF uses the complex index itself (no fresnel=)");
  if (!has_material(keys)) {
    if (required)
      throw InputError(who +
                       ": give the metal's optical constants (metal=, n= and k=, nk_csv=, "
                       "r0= or color=)");
    return std::nullopt;
  }
  return optical_constants(parse_material(keys, std::nullopt, KeyStyle::Python));
}

std::vector<double> values(const py::object& v, const std::vector<double>& fallback) {
  if (v.is_none()) return fallback;
  if (py::isinstance<py::float_>(v) || py::isinstance<py::int_>(v)) return {v.cast<double>()};
  return v.cast<std::vector<double>>();
}

// The centred grid's frequencies along one axis (AreaPsd::fx / fy), cycles/m.
py::array_t<double> frequencies(std::size_t n, double df) {
  py::array_t<double> f(static_cast<py::ssize_t>(n));
  for (std::size_t i = 0; i < n; ++i)
    f.mutable_data()[i] = (static_cast<double>(i) - static_cast<double>(n / 2)) * df;
  return f;
}

py::object mueller(const RayleighRiceBrdf& b, const py::object& wi_obj, const py::object& wo_obj,
                   double wavelength) {
  const Vec3Array wi = vec3_array(wi_obj, "wi"), wo = vec3_array(wo_obj, "wo");
  const std::size_t n = broadcast_count(wi, wo);
  py::array_t<double> out({py::ssize_t(n), py::ssize_t(4), py::ssize_t(4)});
  double* o = out.mutable_data();
  {
    py::gil_scoped_release r;
    for (std::size_t i = 0; i < n; ++i) {
      const auto m = b.mueller(wi[wi.single ? 0 : i], wo[wo.single ? 0 : i], wavelength);
      std::copy(m.begin(), m.end(), o + 16 * i);
    }
  }
  if (wi.single && wo.single) return out[py::int_(0)];
  return out;
}

}  // namespace

void bind_rayleigh_rice(py::module_& m) {
  py::class_<AreaPsd, std::shared_ptr<AreaPsd>>(m, "Psd", R"(The areal PSD of a scan (mb.psd).

Two-sided, ISO 25178-2 / ISO 10110-8 conventions: frequencies in cycles/m, PSD in m^4, sum of
value * dfx * dfy = the window-weighted mean square height (Sq^2 exactly without a window).
value[iy, ix] is at fx[ix], fy[iy] (zero frequency in the middle; read-only views).)")
      .def_property_readonly(
          "value",
          [](py::object self) {
            const auto& p = self.cast<const AreaPsd&>();
            return view(p.value.data(), {py::ssize_t(p.nfy), py::ssize_t(p.nfx)}, self, false);
          },
          "PSD on the grid, m^4, shape (nfy, nfx)")
      .def_property_readonly(
          "fx", [](const AreaPsd& p) { return frequencies(p.nfx, p.dfx); },
          "Frequencies of the columns, cycles/m")
      .def_property_readonly(
          "fy", [](const AreaPsd& p) { return frequencies(p.nfy, p.dfy); },
          "Frequencies of the rows, cycles/m")
      .def_readonly("dfx", &AreaPsd::dfx, "Grid step along fx, cycles/m")
      .def_readonly("dfy", &AreaPsd::dfy, "Grid step along fy, cycles/m")
      .def_readonly("sq", &AreaPsd::sq, "rms height of the scan's valid samples, m")
      .def_readonly("tiles", &AreaPsd::tiles, "Tiles averaged")
      .def_readonly("tile_choice", &AreaPsd::tile_why,
                    "Which tile was used and why (one sentence with the numbers)")
      .def_property_readonly("window", [](const AreaPsd& p) { return to_string(p.window); })
      .def("integral", &AreaPsd::integral, "sum PSD dfx dfy, m^2")
      .def("rms_slope", &AreaPsd::rms_slope, "sqrt(sum (2 pi |f|)^2 PSD dfx dfy)")
      .def(
          "at",
          [](const AreaPsd& p, const py::object& fx, const py::object& fy) {
            const CArray x = CArray::ensure(fx), y = CArray::ensure(fy);
            if (!x || !y || x.size() != y.size())
              throw py::value_error("at: fx and fy must be arrays of the same size");
            py::array_t<double> out(x.size());
            for (py::ssize_t i = 0; i < x.size(); ++i)
              out.mutable_data()[i] = p.at(x.data()[i], y.data()[i]);
            if (x.ndim() == 0) return py::object(py::float_(out.data()[0]));
            return py::object(
                out.reshape(std::vector<py::ssize_t>(x.shape(), x.shape() + x.ndim())));
          },
          py::arg("fx"), py::arg("fy"), "Bilinear interpolation at (fx, fy) cycles/m; 0 outside")
      .def(
          "radial",
          [](const AreaPsd& p) {
            const RadialPsd r = radial_psd(p);
            return py::make_tuple(py::array_t<double>(py::ssize_t(r.f.size()), r.f.data()),
                                  py::array_t<double>(py::ssize_t(r.value.size()), r.value.data()));
          },
          "Azimuthal average: (f in cycles/m, the 2-D PSD's ring means in m^4)")
      .def(
          "to_json", [](const AreaPsd& p) { return json_to_py(psd_json(p)); },
          "The record of `info --json` (units, normalisation, grid, estimator)");

  py::class_<RayleighRiceBrdf, Brdf, std::shared_ptr<RayleighRiceBrdf>>(
      m, "RayleighRiceBrdf",
      "First-order Rayleigh-Rice BRDF: (16 pi^2 / lambda^4) cos_i cos_s Q PSD(f) (diffuse part; "
      "the specular delta is specular_reflectance()).")
      .def("mueller", &mueller, py::arg("wi"), py::arg("wo"), py::arg("wavelength") = 555e-9,
           "Mueller matrices (N, 4, 4) in 1/sr; [0, 0] is the unpolarised BRDF")
      .def(
          "specular_reflectance",
          [](const RayleighRiceBrdf& b, const py::object& wi, double wavelength) {
            const Vec3Array v = vec3_array(wi, "wi");
            return b.specular_reflectance(v[0], wavelength);
          },
          py::arg("wi"), py::arg("wavelength") = 555e-9,
          "R(theta_i) exp(-(4 pi Sq cos theta_i / lambda)^2): the delta lobe")
      .def_property_readonly("psd",
                             [](const RayleighRiceBrdf& b) {
                               return std::const_pointer_cast<AreaPsd>(b.shared_psd());
                             })
      .def_property_readonly("polarisation",
                             [](const RayleighRiceBrdf& b) { return to_string(b.polarisation()); });

  m.def("psd", &psd_of, py::arg("surface"), py::arg("window") = "hann", py::arg("tile") = "auto",
        py::arg("level") = "plane", py::arg("spacing") = py::none(),
        R"(The areal PSD of one scan (ISO 25178 conventions: cycles/m, m^4), as a Psd.

surface: a Surface or a path; level: 'none' | 'plane' | 'polyN' (a Surface is levelled on a copy);
window: 'hann' (default; no edge leakage along the axes) or 'none' (exact Parseval: the integral
is Sq^2 to rounding); tile: 'auto' (default: Welch tiles of 32 correlation lengths when the scan
holds 3 per axis, else the whole scan; one periodogram is speckle), 'whole' or None (one
periodogram of the whole scan), or a side in samples (50 % overlap). Psd.tile_choice says which
and why. See docs/rayleigh_rice.md.)");

  m.def(
      "rayleigh_rice",
      [](const py::object& surface, const std::string& polarisation, const std::string& window,
         const py::object& tile, const std::string& level, const py::object& spacing,
         const py::kwargs& kwargs) {
        const auto material = material_of(kwargs, "rayleigh_rice", true);
        const Polarisation pol = parse_polarisation(polarisation);
        const PsdPtr p = psd_of(surface, window, tile, level, spacing);
        return std::make_shared<RayleighRiceBrdf>(p, *material, pol);
      },
      py::arg("surface"), py::arg("polarisation") = "unpolarised", py::arg("window") = "hann",
      py::arg("tile") = "auto", py::arg("level") = "plane", py::arg("spacing") = py::none(),
      R"(The first-order Rayleigh-Rice BRDF of a smooth metal from the scan's own PSD.

surface: a Surface, a path or a Psd (mb.psd); material keywords as mb.brdf: metal='Al', or n=, k=,
nk_csv=, r0=, color= (the complex index enters Q; no fresnel=). window, tile: as mb.psd (tile
'auto' by default: the PSD averaged over tiles where the scan allows). polarisation: 'unpolarised'
(default), 's' or 'p' (incident; scattered light summed), 'ss', 'sp', 'ps', 'pp'.
The wavelength is given per call, as for every BRDF: b.eval(wi, wo, wavelength=633e-9),
b.mueller(wi, wo, wavelength) (N, 4, 4), mb.tis(b.psd, ...).
Valid while 4 pi Sq cos(theta) / lambda << 1 and the slopes are small (docs/rayleigh_rice.md).

Example: b = mb.rayleigh_rice(s, metal='Al', polarisation='s'))");

  m.def(
      "tis",
      [](const py::object& surface, const py::object& wavelength, const py::object& theta_i,
         const std::string& polarisation, const std::string& window, const py::object& tile,
         const std::string& level, const py::object& spacing, const py::kwargs& kwargs) {
        const auto material = material_of(kwargs, "tis", false);
        const Polarisation pol = parse_polarisation(polarisation);
        const auto wl = values(wavelength, tis_default_wavelengths());
        const auto th = values(theta_i, tis_default_angles());
        for (double l : wl)
          if (!(l >= 100e-9 && l <= 20e-6))
            throw InputError("wavelength must lie in 100 nm .. 20 um (metres)");
        for (double t : th)
          if (!(t >= 0 && t < M_PI / 2)) throw InputError("theta_i must lie in [0, pi/2) rad");
        const PsdPtr p = psd_of(surface, window, tile, level, spacing);
        const nlohmann::json j = call_released(
            [&] { return tis_table(p, material ? &*material : nullptr, wl, th, pol); });
        return json_to_py(j);
      },
      py::arg("surface"), py::arg("wavelength") = py::none(), py::arg("theta_i") = py::none(),
      py::arg("polarisation") = "unpolarised", py::arg("window") = "hann",
      py::arg("tile") = "whole", py::arg("level") = "plane", py::arg("spacing") = py::none(),
      R"(Total integrated scatter per wavelength and angle of incidence, as `info --json`.

surface: a Surface, a path or a Psd (tile: 'whole' by default, one periodogram as `info --json`
takes: a tile's mean removes the power below its frequency step, which the TIS counts);
wavelength (m) and theta_i (rad): numbers or sequences
(default 405, 555, 633, 1064 nm x 0, 20, 45, 70 deg); material keywords as mb.rayleigh_rice.
Returns a list of dicts: rayleigh_factor (4 pi Sq cos theta / lambda)^2 and, with a material,
reflectance, tis_closed_form (= factor x R), tis_integral (the Rayleigh-Rice BRDF over the
hemisphere), integral_over_closed_form, specular_reflectance, propagating_sq_m.)");
}

}  // namespace microbrdf::python
