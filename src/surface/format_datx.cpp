// STUB: to be replaced by the real datx reader/writer.
#include "microbrdf/error.hpp"
#include "surface/formats.hpp"

namespace microbrdf::detail {
Surface read_datx(Bytes, const std::string& name) {
  throw FileError(name, "datx: reading is not implemented yet");
}
}  // namespace microbrdf::detail
