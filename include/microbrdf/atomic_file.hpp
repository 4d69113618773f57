#pragma once
// Atomic output: write to a temporary file beside the target, then rename over it.
// If commit() is never reached (an exception, an interrupt), the temporary is removed and the
// target is untouched: no half-written outputs. Temporaries are registered with the interrupt
// cleanup (microbrdf/interrupt.hpp), so SIGINT / SIGTERM remove them too.
//
// Several outputs of one run are committed together with an OutputGroup: while a group is
// open, AtomicFile::commit() hands its temporary to the group instead of renaming it, and the
// group renames them all at the end (or removes them all): a run that fails on its second
// output leaves the first one untouched.

#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

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

/// All-or-nothing commit of every AtomicFile committed while it is open (one group at a time,
/// process-wide; thread-safe). Destroyed without commit(): every staged temporary is removed.
class OutputGroup {
 public:
  OutputGroup();
  ~OutputGroup();
  OutputGroup(const OutputGroup&) = delete;
  OutputGroup& operator=(const OutputGroup&) = delete;

  /// Renames every staged temporary onto its target, with interrupts held off. Throws
  /// FileError naming the target if a rename fails (the remaining temporaries are removed).
  void commit();

  /// While alive, AtomicFile commits directly again (for writers that stage a whole folder
  /// themselves and rename it, as predict does).
  class Bypass {
   public:
    Bypass();
    ~Bypass();
    Bypass(const Bypass&) = delete;
    Bypass& operator=(const Bypass&) = delete;

   private:
    OutputGroup* saved_;
  };

 private:
  friend class AtomicFile;
  void adopt(const std::string& temp, const std::string& path);
  std::vector<std::pair<std::string, std::string>> staged_;  // temporary, target
  bool done_ = false;
};

/// Writes bytes to `path` atomically. Throws FileError.
void write_file_atomic(const std::string& path, std::span<const std::uint8_t> bytes);
void write_file_atomic(const std::string& path, const std::string& text);

}  // namespace microbrdf
