// The library's errors as Python exceptions: FileError (a file that cannot be read or written,
// or is corrupt) is an OSError whose `filename` names the file; InputError (a bad value) is a
// ValueError. Both are defined in Python so that str(e) reads "<path>: <problem>". The file name
// is decoded as os.fsdecode does (undecodable bytes as surrogate escapes: e.filename names the
// same file), messages with \xNN escapes for bytes that are not UTF-8 (a message quoting a
// corrupt file must not become a UnicodeDecodeError that hides which file it was).
#include <pybind11/eval.h>

#include <cerrno>
#include <filesystem>

#include "bindings.hpp"
#include "microbrdf/error.hpp"

namespace microbrdf::python {
namespace {

constexpr const char* kErrorClasses = R"(
import os as _os


class FileError(OSError):
    """A file that cannot be read or written, or whose content is corrupt, truncated or hostile.

    An OSError: ``filename`` is the file, ``strerror`` the problem, ``errno`` is errno.ENOENT
    when the file does not exist (else None). str(e) is "<path>: <problem>".
    """

    def __init__(self, filename, problem, errno=None):
        super().__init__(errno, problem, filename)

    def __str__(self):
        name = self.filename
        if isinstance(name, str):  # printable even when the name is not valid UTF-8
            name = _os.fsencode(name).decode("utf-8", "backslashreplace")
        return f"{name}: {self.strerror}"


class InputError(ValueError):
    """A bad value that is not a file: an out-of-range parameter, an unknown name."""
)";

py::object g_file_error, g_input_error;

}  // namespace

void bind_errors(py::module_& m) {
  py::dict ns;
  ns["__name__"] = m.attr("__name__");
  py::exec(kErrorClasses, ns, ns);
  m.attr("FileError") = ns["FileError"];
  m.attr("InputError") = ns["InputError"];
  g_file_error = ns["FileError"];
  g_input_error = ns["InputError"];
  // Module-lifetime references: released when the interpreter shuts down.
  py::module_::import("atexit").attr("register")(py::cpp_function([] {
    g_file_error.release().dec_ref();
    g_input_error.release().dec_ref();
  }));
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const FileError& e) {
      std::error_code ec;
      const bool missing = !std::filesystem::exists(e.path(), ec);
      py::object err = missing ? py::object(py::int_(ENOENT)) : py::object(py::none());
      py::object exc = g_file_error(path_text(e.path()), text(e.problem()), err);
      PyErr_SetObject(g_file_error.ptr(), exc.ptr());
    } catch (const InputError& e) {
      PyErr_SetObject(g_input_error.ptr(), text(e.what()).ptr());
    } catch (const std::out_of_range& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
}

}  // namespace microbrdf::python
