// The extension module microbrdf._microbrdf; the package microbrdf re-exports it
// (python/microbrdf).
#include "bindings.hpp"
#include "microbrdf/version.hpp"

namespace microbrdf::python {

Vec3Array vec3_array(const py::handle& obj, const char* what) {
  Vec3Array v;
  v.array = CArray::ensure(obj);
  if (!v.array) throw py::value_error(std::string(what) + ": expected an array of floats");
  if (v.array.ndim() == 1 && v.array.shape(0) == 3) {
    v.n = 1;
    v.single = true;
  } else if (v.array.ndim() == 2 && v.array.shape(1) == 3) {
    v.n = static_cast<std::size_t>(v.array.shape(0));
  } else {
    throw py::value_error(std::string(what) + ": expected shape (N, 3) or (3,)");
  }
  return v;
}

std::size_t broadcast_count(const Vec3Array& a, const Vec3Array& b) {
  if (a.n == b.n || b.single) return a.n;
  if (a.single) return b.n;
  throw py::value_error("direction arrays of different lengths (" + std::to_string(a.n) + " and " +
                        std::to_string(b.n) + ")");
}

std::optional<std::pair<double, double>> length_pair(const py::object& obj, const char* what) {
  if (obj.is_none()) return std::nullopt;
  double dx, dy;
  if (py::isinstance<py::sequence>(obj) && !py::isinstance<py::str>(obj)) {
    auto seq = obj.cast<py::sequence>();
    if (seq.size() != 2) throw py::value_error(std::string(what) + ": give one length or (dx, dy)");
    dx = seq[0].cast<double>();
    dy = seq[1].cast<double>();
  } else {
    dx = dy = obj.cast<double>();
  }
  if (!(dx > 0) || !(dy > 0) || !std::isfinite(dx) || !std::isfinite(dy))
    throw py::value_error(std::string(what) + " must be positive and finite (metres)");
  return std::make_pair(dx, dy);
}

std::string fspath(const py::handle& obj) {
  return py::str(py::module_::import("os").attr("fspath")(obj)).cast<std::string>();
}

bool is_path(const py::handle& obj) {
  return py::isinstance<py::str>(obj) || py::hasattr(obj, "__fspath__");
}

std::vector<std::string> path_list(const py::handle& obj) {
  std::vector<std::string> out;
  if (is_path(obj))
    out.push_back(fspath(obj));
  else
    for (auto item : obj.cast<py::sequence>()) out.push_back(fspath(item));
  return out;
}

py::object json_to_py(const std::string& dumped) {
  return py::module_::import("json").attr("loads")(dumped);
}

}  // namespace microbrdf::python

PYBIND11_MODULE(_microbrdf, m) {
  using namespace microbrdf::python;
  m.doc() =
      "microbrdf: how a metal surface reflects light, predicted from its measured "
      "microgeometry.\n\nSI units throughout (metres, radians); see docs/python.md.";
  m.attr("__version__") = microbrdf::version();
  bind_errors(m);
  bind_surface(m);
  bind_ndf(m);
  bind_fit(m);
  bind_brdf(m);
  bind_simulate(m);
  bind_render(m);
  bind_measured(m);
}
