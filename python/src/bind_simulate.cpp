// Westin 1992 simulation of a micro-scene -> ShBrdf (a Brdf with its SH matrix as a view).
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "microbrdf/brdf.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/microscene.hpp"
#include "microbrdf/sh_basis.hpp"
#include "microbrdf/sh_brdf.hpp"
#include "microbrdf/simulate.hpp"

namespace microbrdf::python {
namespace {

std::shared_ptr<ShBrdf> simulate_scene(const py::object& scene, int lmax, std::uint64_t rays,
                                       int points, int branches, int max_depth, std::uint64_t seed,
                                       int threads, bool independent, double time,
                                       const py::object& progress) {
  const std::string path = fspath(scene, "scene");
  if (points < 1) throw InputError("points must be >= 1");
  if (branches < 1) throw InputError("branches must be >= 1");
  if (max_depth < 1) throw InputError("max_depth must be >= 1");
  if (time < 0) throw InputError("time must be >= 0 (seconds)");
  SimulateOptions o;
  o.lmax = lmax;
  o.points = points;
  o.trace.branches = branches;
  o.trace.max_depth = max_depth;
  o.seed = seed;
  o.threads = threads;
  o.stratify = !independent;
  o.time_limit_s = time;
  o.incident_directions = std::max<std::uint64_t>(1, rays / std::uint64_t(points));
  auto hook = progress_hook<double>(progress);
  // Called on the calling thread as blocks of directions are folded in: Ctrl-C may unwind here.
  o.progress = [&, total = double(o.incident_directions)](std::uint64_t dirs, std::uint64_t,
                                                          double t, double) {
    hook(time > 0 ? std::min(1.0, t / time) : double(dirs) / total);
  };
  return call_released([&] {
    const MicroScene ms(load_micro_scene(path));
    SimulateStats st;
    const ShEstimator est = simulate(ms, o, &st);
    nlohmann::json meta = {{"generator", "microbrdf simulate (Westin 1992)"},
                           {"scene", path},
                           {"scene_name", ms.desc().name},
                           {"scene_json", ms.desc().source},
                           {"wavelength_m", ms.desc().wavelength_m},
                           {"seed", seed},
                           {"points_per_direction", points},
                           {"branches", branches},
                           {"max_depth", max_depth},
                           {"stratified", o.stratify},
                           {"stats", st.to_json()}};
    return std::make_shared<ShBrdf>(ShBrdf::from_estimator(est, meta));
  });
}

}  // namespace

void bind_simulate(py::module_& m) {
  py::class_<ShBrdf, Brdf, std::shared_ptr<ShBrdf>>(
      m, "ShBrdf", R"(A BRDF as a matrix of real spherical-harmonic coefficients (Westin 1992).

rho(wi, wo) cos(theta_i) cos(theta_o) = Y(wi)^T M Y(wo) over the basis functions with l + m odd,
l <= lmax. `matrix` is a read-only float64 view of M (no copy).)")
      .def_property_readonly("lmax", [](const ShBrdf& b) { return b.basis().lmax(); })
      .def_property_readonly(
          "matrix",
          [](py::object self) {
            const auto& b = self.cast<const ShBrdf&>();
            const auto& M = b.matrix();
            // Eigen is column-major; M is symmetric, so the (row-major) view reads the same.
            return view(M.data(), {py::ssize_t(M.rows()), py::ssize_t(M.cols())}, self, false);
          },
          "The symmetric SH matrix M, (J, J) with J = lmax (lmax + 1) / 2: a read-only view.")
      .def_property_readonly(
          "metadata", [](const ShBrdf& b) { return json_to_py(b.meta()); },
          "Where it came from: scene, seed, rays, Q, wavelength_m, ...")
      .def("isotropic_average", &ShBrdf::isotropic_average,
           "The average over rotations about n (the isotropic part).")
      .def("damped", &ShBrdf::damped, py::arg("l_filter"), py::arg("width"),
           "Gibbs attenuation: coefficients above l_filter damped by exp(-(l - l_filter)^2 / "
           "(2 width^2)).")
      .def(
          "save",
          [](const ShBrdf& b, const py::object& path) {
            const std::string p = fspath(path, "path");
            call_released([&] { b.save(p); });
          },
          py::arg("path"), "Writes the .shbrdf file `microbrdf simulate -o` writes. Atomic.")
      .def_static(
          "load",
          [](const py::object& path) {
            const std::string p = fspath(path, "path");
            return call_released([&] { return std::make_shared<ShBrdf>(ShBrdf::load(p)); });
          },
          py::arg("path"), "Reads a .shbrdf file; FileError naming it when corrupt.");

  m.def(
      "simulate", &simulate_scene, py::arg("scene"), py::arg("lmax") = 15,
      py::arg("rays") = 2000000, py::arg("points") = 16, py::arg("branches") = 1,
      py::arg("max_depth") = 100, py::arg("seed") = 1, py::arg("threads") = 0,
      py::arg("independent") = false, py::arg("time") = 0.0, py::arg("progress") = py::none(),
      R"(Westin 1992 Monte Carlo BRDF of a micro-scene, as `microbrdf simulate`; returns an ShBrdf.

scene: the micro-scene JSON file (docs/westin.md). lmax: highest SH order. rays: incident rays
in all (N_i N_p; N_i = rays // points directions). points: N_p target points per direction.
branches: N_b rays at the first diffuse event. max_depth: events before a path is cut.
seed: the same seed and thread count give the same matrix. threads: 0 = all cores.
independent: independent uniform incident directions instead of stratified rounds.
time: > 0 runs for this many seconds instead of `rays` (not deterministic).
progress: optional callable(fraction), called about once a second from the calling thread.
Runs without the GIL; Ctrl-C interrupts it (checked about once a second, as blocks of directions
are folded in).)");
}

}  // namespace microbrdf::python
