#pragma once
// The version of the library a program runs against (the CMake project version, e.g. "0.1.0"):
// what `microbrdf --version`, predict's provenance record and Python's microbrdf.__version__
// print. A program built against an installed microbrdf can compare it with the version its
// find_package() or pkg-config found.

namespace microbrdf {

/// "MAJOR.MINOR.PATCH" of the compiled library (a static string).
const char* version();

}  // namespace microbrdf
