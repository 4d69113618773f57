// STUB: to be replaced by the real gwy reader/writer.
#include "microbrdf/error.hpp"
#include "surface/formats.hpp"

namespace microbrdf::detail {
Surface read_gwy(Bytes, const std::string& name) {
  throw FileError(name, "gwy: reading is not implemented yet");
}
void write_gwy(const Surface&, const std::string& path) {
  throw FileError(path, "gwy: writing is not implemented yet");
}
}  // namespace microbrdf::detail
