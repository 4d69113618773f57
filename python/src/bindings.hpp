#pragma once
// Pieces every binding file shares: the registration functions, (N, 3) direction arrays in and
// out, and the guard that runs a long library call without the GIL while keeping Ctrl-C and an
// optional Python progress callback alive.
#include <omp.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "microbrdf/io.hpp"
#include "microbrdf/level.hpp"
#include "microbrdf/surface.hpp"

namespace microbrdf::python {

namespace py = pybind11;

void bind_errors(py::module_& m);
void bind_surface(py::module_& m);
void bind_ndf(py::module_& m);
void bind_fit(py::module_& m);
void bind_brdf(py::module_& m);
void bind_rayleigh_rice(py::module_& m);
void bind_simulate(py::module_& m);
void bind_render(py::module_& m);
void bind_measured(py::module_& m);

/// A float64, C-contiguous array: one that already is one is taken as it is (no copy); anything
/// else numpy converts once (forcecast).
using CArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// A stack of 3-vectors: shape (N, 3), or (3,) for one vector (N = 1). Reads the array in place.
struct Vec3Array {
  CArray array;
  std::size_t n = 0;
  bool single = false;  ///< the input was one vector (3,)
  Eigen::Vector3d operator[](std::size_t i) const {
    const double* p = array.data() + 3 * i;
    return {p[0], p[1], p[2]};
  }
};
/// Checks the shape; throws ValueError naming `what` otherwise.
Vec3Array vec3_array(const py::handle& obj, const char* what);
/// The count two stacks broadcast to (equal, or one of them a single vector); ValueError else.
std::size_t broadcast_count(const Vec3Array& a, const Vec3Array& b);

/// An array viewing `data` (no copy), kept alive by `owner`.
template <class T>
py::array view(const T* data, std::vector<py::ssize_t> shape, py::handle owner,
               bool writable = true) {
  py::array a(py::dtype::of<T>(), std::move(shape), {}, data, owner);
  if (!writable)
    py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

/// Thrown from inside a library call (through its progress hook) when Ctrl-C was pressed or the
/// Python progress callback raised; the Python error is already set and is re-raised once the
/// call has unwound and the GIL is back (call_released).
struct Interrupted {};

/// Text from the library or from a file (a message, a comment, a metadata value) as a str;
/// bytes that are not UTF-8 are shown as \xNN escapes instead of raising UnicodeDecodeError.
py::str text(const std::string& s);
/// A path as a str, as os.fsdecode gives it (undecodable bytes as surrogate escapes, so the
/// str names the same file).
py::str path_text(const std::string& s);
/// An argument of a Python callback: text (a progress line naming a file) decoded with escapes.
inline py::str callback_arg(const std::string& s) { return text(s); }
template <class T>
T callback_arg(T v) {
  return v;
}

/// Progress for the library: a std::function that, when called from the thread running the
/// call, takes the GIL, calls the user's callback (if any) with the arguments, and checks for
/// Ctrl-C; either failing throws Interrupted (the Python error stays set). Inside an OpenMP
/// parallel region (the renderer reports from its thread 0) an exception cannot unwind, so the
/// failure is remembered and thrown at the next call made outside one.
/// Create it while holding the GIL; it may then be copied and destroyed anywhere (the callback
/// is shared, and released under the GIL).
template <class... Args>
std::function<void(Args...)> progress_hook(const py::object& callback) {
  std::shared_ptr<py::object> cb(new py::object(callback), [](py::object* p) {
    py::gil_scoped_acquire gil;
    delete p;
  });
  auto failed = std::make_shared<bool>(false);
  return [cb, failed](Args... args) {
    py::gil_scoped_acquire gil;
    if (!*failed) {
      if (!cb->is_none()) {
        try {
          (*cb)(callback_arg(args)...);
        } catch (py::error_already_set& e) {
          e.restore();
          *failed = true;
        }
      }
      if (!*failed && PyErr_CheckSignals() != 0) *failed = true;
    }
    if (*failed && !omp_in_parallel()) throw Interrupted{};
  };
}

/// Runs `f` without the GIL; an Interrupted from a hook becomes the Python error it stands for.
/// So does any other exception while that error is pending: library code that runs work items
/// (distribute.hpp) reports an exception from a hook as its own error. Anything else propagates
/// to the exception translators.
template <class F>
auto call_released(F&& f) -> decltype(f()) {
  try {
    py::gil_scoped_release release;
    return f();
  } catch (Interrupted&) {
    throw py::error_already_set();
  } catch (...) {
    if (PyErr_Occurred()) throw py::error_already_set();
    throw;
  }
}

/// The path `obj` names (str, bytes or os.PathLike) as the bytes os.fsencode gives: names
/// with undecodable bytes (surrogate escapes) keep their bytes. `what` names the argument in
/// the errors: InputError (a ValueError) for a NUL character or a str that cannot be
/// encoded; TypeError for anything that is not a path.
std::string fspath(const py::handle& obj, const std::string& what);
/// Whether obj names a file (str, bytes or os.PathLike).
bool is_path(const py::handle& obj);
/// One path, or a sequence of paths, as fspath gives them.
std::vector<std::string> path_list(const py::handle& obj, const std::string& what);

/// Refuses a count argument whose arrays would exceed the memory budget (memory_budget.hpp):
/// InputError "<what>: needs 24 TiB for <purpose>, over the memory budget of ...".
void check_count(const std::string& what, std::uint64_t count, std::uint64_t bytes_each,
                 const std::string& purpose);

/// Lengths: a float in metres, or a (dx, dy) pair; nothing for None.
std::optional<std::pair<double, double>> length_pair(const py::object& obj, const char* what);

/// A JSON value as Python objects (dicts, lists, numbers, strings, None, bools); strings that
/// are not UTF-8 get U+FFFD replacement characters.
py::object json_to_py(const nlohmann::json& j);
/// (Not from a dumped text: a std::string would silently become one JSON string.)
py::object json_to_py(const std::string&) = delete;

// ---- scans: Surface objects or paths -------------------------------------------------------

/// What functions taking scans accept: one Surface, one path (str or os.PathLike, which may be a
/// glob, a directory or an @manifest, as on the command line), or a list of those.
struct ScanInputs {
  std::vector<std::shared_ptr<const Surface>> surfaces;  ///< in order; null where a path stands
  std::vector<std::string> paths;                        ///< "" where a Surface stands
  std::size_t size() const { return surfaces.size(); }
};
ScanInputs scan_inputs(const py::object& obj);
ReadOptions read_options(const py::object& spacing);

/// Scan i, levelled as asked: a path is read (without the GIL) and levelled in place; a
/// Surface is used as it is for level "none", else levelled on a copy. `keep` holds the copy.
const Surface& load_scan(const ScanInputs& in, std::size_t i, const ReadOptions& read,
                         const LevelingSpec& level, Surface& keep);

}  // namespace microbrdf::python
