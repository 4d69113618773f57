#pragma once
// --threads as given, bounded: more than the sane maximum is clamped with a note on stderr.
namespace microbrdf::cli {

/// Returns `requested` (0 = every core), or the maximum with a note when it is larger.
int bounded_threads(const char* command, int requested);

}  // namespace microbrdf::cli
