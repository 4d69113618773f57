#pragma once
// Atomic output: write to a temporary file beside the target, then rename over it.
// If commit() is never reached (an exception, a crash), the temporary is removed and the
// target is untouched: no half-written outputs.

#include <cstdint>
#include <span>
#include <string>

namespace microbrdf {

class AtomicFile {
 public:
  /// Chooses a temporary name "<path>.tmp-<pid>-<n>" in the target's directory.
  explicit AtomicFile(std::string path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  const std::string& temp_path() const { return temp_; }
  const std::string& path() const { return path_; }
  /// Renames the temporary onto the target. Throws FileError if the rename fails.
  void commit();

 private:
  std::string path_;
  std::string temp_;
  bool committed_ = false;
};

/// Writes bytes to `path` atomically. Throws FileError.
void write_file_atomic(const std::string& path, std::span<const std::uint8_t> bytes);
void write_file_atomic(const std::string& path, const std::string& text);

}  // namespace microbrdf
