// STUB: to be replaced by the real plu reader/writer.
#include "microbrdf/error.hpp"
#include "surface/formats.hpp"

namespace microbrdf::detail {
Surface read_plu(Bytes, const std::string& name) {
  throw FileError(name, "plu: reading is not implemented yet");
}
}  // namespace microbrdf::detail
