#pragma once
// Reading input files whole, safely: only regular files (a FIFO or a device would block or
// never end), never more than a size cap.
#include <cstdint>
#include <string>
#include <vector>

namespace microbrdf {

/// Throws FileError unless `path` names an existing regular file (symbolic links followed):
/// "no such file", "is a directory", "is not a regular file (a FIFO, socket or device)".
/// Records the file as an input of the open run (microbrdf/run_inputs.hpp): every reader calls
/// this first, so no output of the run can replace a file it read.
void require_regular_file(const std::string& path);

/// Reads a whole regular file into memory, refusing files over `max_bytes`. Throws FileError.
std::vector<std::uint8_t> read_file_bytes(const std::string& path, std::uint64_t max_bytes);

}  // namespace microbrdf
