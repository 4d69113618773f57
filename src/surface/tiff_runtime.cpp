// Loads libtiff by its soname the first time a TIFF is read (tiff_runtime.hpp says why).
#include "surface/tiff_runtime.hpp"

#include "microbrdf/error.hpp"

#ifndef MICROBRDF_TIFF_SONAME
#error "MICROBRDF_TIFF_SONAME (the soname of the libtiff built against) is set by CMakeLists.txt"
#endif
#ifndef MICROBRDF_TIFF_PACKAGE
#define MICROBRDF_TIFF_PACKAGE "the libtiff runtime library"
#endif

namespace microbrdf::detail {

void load_tiff(const std::string& name) {
  static const std::string error =
      load_runtime_library(MICROBRDF_TIFF_SONAME, MICROBRDF_TIFF_PACKAGE,
                           {MICROBRDF_TIFF_FUNCTIONS(MICROBRDF_RUNTIME_SYMBOL)});
  if (!error.empty()) throw FileError(name, "reading TIFF needs " + error);
}

}  // namespace microbrdf::detail
