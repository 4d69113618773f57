#pragma once
// A scan set: many scans named by a list of paths, glob patterns, directories, or manifest
// files, processed one at a time so memory does not grow with the number of scans.

#include <functional>
#include <string>
#include <vector>

#include "microbrdf/distribute.hpp"
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

/// The scans of a set over all ranks and threads (distribute.hpp): each scan is read with
/// `options` on whichever rank takes it and handed to `compute` (index, path, surface), which
/// returns what rank 0 needs of it; `consume` runs on rank 0 in scan order. A rank holds one
/// surface per thread at a time. A read error names the file (FileError) and ends the run on
/// every rank.
WorkStats distribute_scans(
    const std::vector<std::string>& paths, const ReadOptions& options,
    const std::function<WorkResult(std::size_t, const std::string&, Surface&)>& compute,
    const std::function<void(std::size_t, WorkResult&&)>& consume,
    const DistributeOptions& distribute_options = {});

}  // namespace microbrdf
