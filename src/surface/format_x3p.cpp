// STUB: to be replaced by the real x3p reader/writer.
#include "microbrdf/error.hpp"
#include "surface/formats.hpp"

namespace microbrdf::detail {
Surface read_x3p(Bytes, const std::string& name) {
  throw FileError(name, "x3p: reading is not implemented yet");
}
void write_x3p(const Surface&, const std::string& path) {
  throw FileError(path, "x3p: writing is not implemented yet");
}
}  // namespace microbrdf::detail
