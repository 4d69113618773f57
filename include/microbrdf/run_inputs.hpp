#pragma once
// The input files of one run, so that no output of the run can replace one of them
// (`microbrdf ndf a.npy -o a.npy` would otherwise replace the scan, and its sidecar a.json, by
// the NDF). While a RunInputs scope is open (the command line opens one around each command),
// every file a reader opens (require_regular_file, microbrdf/file_read.hpp) is recorded by
// device and inode; committing an output (microbrdf/atomic_file.hpp) whose target is one of
// those files, under any spelling of its path (a symbolic link, a hard link, "./a.npy"), throws
// FileError before anything is renamed. Outside a scope (library and Python use) nothing is
// recorded: a program may well read a file and then deliberately write it back.
#include <string>

namespace microbrdf {

class RunInputs {
 public:
  RunInputs();   ///< starts recording (scopes do not nest: the outer one keeps recording)
  ~RunInputs();  ///< forgets what was recorded
  RunInputs(const RunInputs&) = delete;
  RunInputs& operator=(const RunInputs&) = delete;

 private:
  bool owner_ = false;
};

/// Records `path` as an input of the open run (no-op without a RunInputs scope, or when the
/// file does not exist). Thread-safe.
void record_input(const std::string& path);

/// Throws FileError(target, "is an input of this run ...") when `target` exists and is a file
/// recorded as an input of the open run.
void refuse_replacing_input(const std::string& target);

/// The same for a folder that is about to be replaced as a whole: throws when an input of the
/// run lies anywhere inside `dir`.
void refuse_replacing_inputs_under(const std::string& dir);

}  // namespace microbrdf
