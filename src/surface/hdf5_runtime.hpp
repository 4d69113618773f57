#pragma once
// libhdf5, loaded when a .datx is first read instead of at process start
// (core/runtime_library.hpp says why and how). About 30 shared libraries come with it (libcurl,
// its TLS and Kerberos stack, libsz). The reader loads it before it forks the child that decodes
// the file (surface/isolated_reader.hpp), so a process that reads no .datx never maps them.
#include <hdf5.h>

#include <string>

#include "core/runtime_library.hpp"

// Every function the .datx reader calls, by its real symbol name (H5Dopen2, not the H5Dopen
// macro). H5open and H5check_version are called by HDF5's own macros (H5T_NATIVE_DOUBLE,
// H5F_ACC_RDONLY).
#if H5_VERSION_GE(1, 12, 0)
#define MICROBRDF_HDF5_RECLAIM(X) X(H5Treclaim)
#else
#define MICROBRDF_HDF5_RECLAIM(X) X(H5Dvlen_reclaim)
#endif
// clang-format off
#define MICROBRDF_HDF5_FUNCTIONS(X) \
  X(H5open) X(H5check_version) X(H5Aclose) X(H5Aexists) X(H5Aget_space) \
  X(H5Aget_type) X(H5Aopen) X(H5Aread) X(H5Dclose) X(H5Dget_create_plist) \
  X(H5Dget_offset) X(H5Dget_space) X(H5Dget_type) X(H5Dopen2) X(H5Dread) \
  X(H5Eset_auto2) X(H5Fclose) X(H5Fopen) X(H5Gclose) X(H5Gget_info) X(H5Gopen2) \
  X(H5Iget_type) X(H5Lexists) X(H5Lget_info) X(H5Lget_name_by_idx) X(H5Oclose) \
  X(H5Oopen) X(H5Pclose) X(H5Pcreate) X(H5Pget_filter2) X(H5Pget_layout) \
  X(H5Pget_nfilters) X(H5Pset_fapl_core) X(H5Pset_file_image) X(H5Sclose) \
  X(H5Sget_simple_extent_dims) X(H5Sget_simple_extent_ndims) \
  X(H5Sget_simple_extent_npoints) X(H5Sget_simple_extent_type) X(H5Tclose) \
  X(H5Tcopy) X(H5Tcreate) X(H5Tget_class) X(H5Tget_member_class) \
  X(H5Tget_member_index) X(H5Tget_member_offset) X(H5Tget_member_type) \
  X(H5Tget_nmembers) X(H5Tget_size) X(H5Tget_super) X(H5Tinsert) \
  X(H5Tis_variable_str) X(H5Tset_size) X(H5Tvlen_create) X(H5Zfilter_avail) \
  X(H5free_memory) MICROBRDF_HDF5_RECLAIM(X)
// clang-format on

namespace microbrdf {
MICROBRDF_HDF5_FUNCTIONS(MICROBRDF_RUNTIME_DECLARE)
// The library's global identifiers behind H5T_NATIVE_DOUBLE, H5T_NATIVE_LLONG, H5T_C_S1 and
// H5P_FILE_ACCESS (each of those macros reads "H5open(), <global>"): copied by load_hdf5 after
// H5open() has set them.
inline hid_t H5T_NATIVE_DOUBLE_g = -1;
inline hid_t H5T_NATIVE_LLONG_g = -1;
inline hid_t H5T_C_S1_g = -1;
inline hid_t H5P_CLS_FILE_ACCESS_ID_g = -1;
}  // namespace microbrdf

namespace microbrdf::detail {

/// Loads libhdf5 (once per process; thread-safe). Throws FileError(name, ...) naming the
/// library and the Debian package when it cannot be loaded or lacks a symbol.
void load_hdf5(const std::string& name);

/// The soname loaded (e.g. libhdf5_serial.so.103), for messages and tests.
const char* hdf5_soname() noexcept;

}  // namespace microbrdf::detail
