#pragma once
// A scan set: many scans named by a list of paths, glob patterns, directories, or manifest
// files, processed one at a time so memory does not grow with the number of scans.

#include <functional>
#include <string>
#include <vector>

#include "microbrdf/io.hpp"
#include "microbrdf/surface.hpp"

namespace microbrdf {

/// Expands inputs into an ordered list of scan files:
///  - a directory: every file in it (not recursive) with a readable extension, sorted by name;
///  - a pattern with * ? or [ ]: the matching files, sorted;
///  - "@FILE": a manifest, one path per line, relative to the manifest's folder; blank lines and
///    lines starting with '#' are ignored;
///  - anything else: taken as a file path as is.
/// Throws FileError for a pattern that matches nothing, an empty directory, an unreadable
/// manifest.
std::vector<std::string> expand_scan_inputs(const std::vector<std::string>& inputs);

/// Reads the scans one after another and hands each to `fn` (index, path, surface); only one
/// Surface is alive at a time. Errors from reading propagate (FileError naming the file).
void for_each_scan(const std::vector<std::string>& paths, const ReadOptions& options,
                   const std::function<void(std::size_t, const std::string&, Surface&)>& fn);

}  // namespace microbrdf
