#pragma once
// libtiff, loaded when a TIFF height map is first read instead of at process start
// (core/runtime_library.hpp says why and how; libtiff brings its codecs: WebP, LERC, JBIG,
// JPEG, libdeflate, zstd, lzma).
#include <tiffio.h>

#include <string>

#include "core/runtime_library.hpp"

/// Every libtiff function the TIFF reader calls.
// clang-format off
#define MICROBRDF_TIFF_FUNCTIONS(X) \
  X(TIFFClientOpenExt) X(TIFFClose) X(TIFFGetField) X(TIFFGetFieldDefaulted) \
  X(TIFFIsCODECConfigured) X(TIFFIsTiled) X(TIFFOpenOptionsAlloc) \
  X(TIFFOpenOptionsFree) X(TIFFOpenOptionsSetErrorHandlerExtR) \
  X(TIFFOpenOptionsSetMaxSingleMemAlloc) X(TIFFOpenOptionsSetWarningHandlerExtR) \
  X(TIFFReadScanline) X(TIFFReadTile) X(TIFFScanlineSize) X(TIFFTileSize)
// clang-format on

namespace microbrdf {
MICROBRDF_TIFF_FUNCTIONS(MICROBRDF_RUNTIME_DECLARE)
}  // namespace microbrdf

namespace microbrdf::detail {

/// Loads libtiff (once per process; thread-safe). Throws FileError(name, ...) naming the library
/// and the Debian package when it cannot be loaded or lacks a symbol.
void load_tiff(const std::string& name);

}  // namespace microbrdf::detail
