// STUB: to be replaced by the real sur reader/writer.
#include "microbrdf/error.hpp"
#include "surface/formats.hpp"

namespace microbrdf::detail {
Surface read_sur(Bytes, const std::string& name) {
  throw FileError(name, "sur: reading is not implemented yet");
}
}  // namespace microbrdf::detail
