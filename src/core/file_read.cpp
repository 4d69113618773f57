#include "microbrdf/file_read.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "microbrdf/error.hpp"
#include "microbrdf/memory_budget.hpp"
#include "microbrdf/run_inputs.hpp"

namespace microbrdf {
namespace fs = std::filesystem;

void require_regular_file(const std::string& path) {
  std::error_code ec;
  const auto st = fs::status(path, ec);
  if (st.type() == fs::file_type::not_found) throw FileError::missing(path);
  if (ec) throw FileError(path, "cannot access: " + ec.message());
  if (st.type() == fs::file_type::directory) throw FileError(path, "is a directory, not a file");
  if (st.type() != fs::file_type::regular)
    throw FileError(path, "is not a regular file (a FIFO, socket or device): give a file on disk");
  record_input(path);  // no output of this run may replace it (microbrdf/run_inputs.hpp)
}

std::vector<std::uint8_t> read_file_bytes(const std::string& path, std::uint64_t max_bytes) {
  require_regular_file(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(path, std::string("cannot open: ") + std::strerror(errno));
  in.seekg(0, std::ios::end);
  std::streamoff n = in.tellg();
  if (n < 0) throw FileError(path, "cannot determine file size");
  if (static_cast<std::uint64_t>(n) > max_bytes)
    throw FileError(path, "file is " + std::to_string(n) + " bytes, over the limit of " +
                              std::to_string(max_bytes));
  check_memory(path, static_cast<std::uint64_t>(n), "the file's bytes");
  in.seekg(0);
  std::vector<std::uint8_t> data(static_cast<std::size_t>(n));
  in.read(reinterpret_cast<char*>(data.data()), n);
  if (!in) throw FileError(path, "read error");
  return data;
}

}  // namespace microbrdf
