// The project version comes from CMakeLists.txt (project(... VERSION)) as a definition on this
// file only, so a version bump recompiles one file and the number is written in one place.
#include "microbrdf/version.hpp"

#ifndef MICROBRDF_VERSION
#error "MICROBRDF_VERSION must be defined by the build (CMakeLists.txt)"
#endif

namespace microbrdf {

const char* version() { return MICROBRDF_VERSION; }

}  // namespace microbrdf
