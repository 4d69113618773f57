#pragma once
// The file-size limit (`ulimit -f`, RLIMIT_FSIZE) reported like a full disk.
//
// By default the kernel ends a process that writes past the limit with SIGXFSZ: no message, and
// the temporary outputs stay behind. install_file_size_limit_handler() catches the signal
// instead (the write then fails with EFBIG, as on a full disk, and the writer throws) and
// remembers that it happened, so that the error names the limit rather than a vague write
// failure, and so that no output is committed after a write was cut short, even by a writer
// that did not check its writes.
#include <string>

namespace microbrdf {

/// Call once at the start of main() (the CLI; Python already ignores SIGXFSZ).
void install_file_size_limit_handler();
/// Whether a write of this process went past the file-size limit.
bool file_size_limit_reached();
/// "the file size limit (ulimit -f: 100 KiB) was reached; as on a full disk, no output was
/// written" (the limit read at the call).
std::string file_size_limit_problem();
/// The problem to report for a write that failed with errno `err`: the file-size limit (EFBIG, or
/// the limit reached earlier), a full disk (ENOSPC), else the system's message.
std::string write_failure_problem(int err);

}  // namespace microbrdf
