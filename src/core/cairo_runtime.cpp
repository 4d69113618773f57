// Loads Cairo by its soname the first time something is drawn (cairo_runtime.hpp says why).
#include "core/cairo_runtime.hpp"

#include <stdexcept>
#include <string>

#ifndef MICROBRDF_CAIRO_SONAME
#error "MICROBRDF_CAIRO_SONAME (the soname of the Cairo built against) is set by CMakeLists.txt"
#endif
#ifndef MICROBRDF_CAIRO_PACKAGE
#define MICROBRDF_CAIRO_PACKAGE "the Cairo runtime library"
#endif

namespace microbrdf::detail {

void load_cairo() {
  static const std::string error =
      load_runtime_library(MICROBRDF_CAIRO_SONAME, MICROBRDF_CAIRO_PACKAGE,
                           {MICROBRDF_CAIRO_FUNCTIONS(MICROBRDF_RUNTIME_SYMBOL)});
  if (!error.empty()) throw std::runtime_error("plots and image labels need " + error);
}

}  // namespace microbrdf::detail
