// STUB: to be replaced by the real exr reader/writer.
#include "microbrdf/error.hpp"
#include "surface/formats.hpp"

namespace microbrdf::detail {
Surface read_exr(Bytes, const std::string& name, const ReadOptions&) {
  throw FileError(name, "exr: reading is not implemented yet");
}
}  // namespace microbrdf::detail
