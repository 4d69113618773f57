// STUB: to be replaced by the real metropro reader/writer.
#include "microbrdf/error.hpp"
#include "surface/formats.hpp"

namespace microbrdf::detail {
Surface read_metropro_dat(Bytes, const std::string& name) {
  throw FileError(name, "metropro: reading is not implemented yet");
}
}  // namespace microbrdf::detail
