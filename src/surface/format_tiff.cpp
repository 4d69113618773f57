// STUB: to be replaced by the real tiff reader/writer.
#include "microbrdf/error.hpp"
#include "surface/formats.hpp"

namespace microbrdf::detail {
Surface read_tiff(Bytes, const std::string& name, const ReadOptions&) {
  throw FileError(name, "tiff: reading is not implemented yet");
}
}  // namespace microbrdf::detail
