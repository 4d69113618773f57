// STUB: to be replaced by the real ascii reader/writer.
#include "microbrdf/error.hpp"
#include "surface/formats.hpp"

namespace microbrdf::detail {
Surface read_ascii(Bytes, const std::string& name, const ReadOptions&) {
  throw FileError(name, "ascii: reading is not implemented yet");
}
void write_ascii_xyz(const Surface&, const std::string& path) {
  throw FileError(path, "ascii: writing is not implemented yet");
}
void write_ascii_grid(const Surface&, const std::string& path) {
  throw FileError(path, "ascii: writing is not implemented yet");
}
}  // namespace microbrdf::detail
