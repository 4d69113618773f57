// Loads libhdf5 by its soname the first time a .datx is read (hdf5_runtime.hpp says why).
#include "surface/hdf5_runtime.hpp"

#include <mutex>

#include "microbrdf/error.hpp"

#ifndef MICROBRDF_HDF5_SONAME
#error "MICROBRDF_HDF5_SONAME (the soname of the libhdf5 built against) is set by CMakeLists.txt"
#endif
#ifndef MICROBRDF_HDF5_PACKAGE
#define MICROBRDF_HDF5_PACKAGE "the HDF5 runtime library"
#endif

namespace microbrdf::detail {

const char* hdf5_soname() noexcept { return MICROBRDF_HDF5_SONAME; }

void load_hdf5(const std::string& name) {
  static const std::string error = [] {
    const hid_t* globals[4] = {};
    std::string e = load_runtime_library(
        MICROBRDF_HDF5_SONAME, MICROBRDF_HDF5_PACKAGE,
        {MICROBRDF_HDF5_FUNCTIONS(MICROBRDF_RUNTIME_SYMBOL)
             RuntimeSymbol{"H5T_NATIVE_DOUBLE_g", &globals[0]},
         RuntimeSymbol{"H5T_NATIVE_LLONG_g", &globals[1]}, RuntimeSymbol{"H5T_C_S1_g", &globals[2]},
         RuntimeSymbol{"H5P_CLS_FILE_ACCESS_ID_g", &globals[3]}});
    if (!e.empty()) return e;
    if (microbrdf::H5open() < 0) return std::string(MICROBRDF_HDF5_SONAME) + ": H5open failed";
    microbrdf::H5T_NATIVE_DOUBLE_g = *globals[0];
    microbrdf::H5T_NATIVE_LLONG_g = *globals[1];
    microbrdf::H5T_C_S1_g = *globals[2];
    microbrdf::H5P_CLS_FILE_ACCESS_ID_g = *globals[3];
    return std::string();
  }();
  if (!error.empty()) throw FileError(name, "reading .datx needs " + error);
}

}  // namespace microbrdf::detail
