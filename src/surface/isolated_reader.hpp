#pragma once
// Runs a reader in a forked child process and brings the Surface back through a pipe.
//
// Why: some third-party decoders (libhdf5 1.10 for .datx) leak, crash or request absurd
// allocations on corrupt files, and no amount of validation beforehand catches every case. In
// a child, a crash, a leak, a runaway allocation or a hang (killed after `timeout_s`) cannot
// hurt the calling process: it becomes FileError(name, ...). A FileError thrown by the reader
// in the child is passed back as is. Set MICROBRDF_NO_ISOLATION=1 to run in-process (debugging).

#include <functional>
#include <string>

#include "microbrdf/surface.hpp"

namespace microbrdf::detail {

Surface read_isolated(const std::string& name, const std::string& library,
                      const std::function<Surface()>& reader, unsigned timeout_s = 120);

}  // namespace microbrdf::detail
