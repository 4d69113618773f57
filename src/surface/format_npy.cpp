// STUB: to be replaced by the real npy reader/writer.
#include "microbrdf/error.hpp"
#include "surface/formats.hpp"

namespace microbrdf::detail {
Surface read_npy(Bytes, const std::string& name, const ReadOptions&) {
  throw FileError(name, "npy: reading is not implemented yet");
}
void write_npy(const Surface&, const std::string& path) {
  throw FileError(path, "npy: writing is not implemented yet");
}
}  // namespace microbrdf::detail
