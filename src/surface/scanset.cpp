#include "microbrdf/scanset.hpp"

#include <glob.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "microbrdf/error.hpp"
#include "microbrdf/file_read.hpp"

namespace microbrdf {
namespace fs = std::filesystem;

namespace {

bool has_glob_chars(const std::string& s) { return s.find_first_of("*?[") != std::string::npos; }

std::vector<std::string> glob_files(const std::string& pattern) {
  glob_t g{};
  int rc = ::glob(pattern.c_str(), 0, nullptr, &g);
  std::vector<std::string> out;
  if (rc == 0)
    for (std::size_t i = 0; i < g.gl_pathc; ++i) out.emplace_back(g.gl_pathv[i]);
  ::globfree(&g);
  if (out.empty()) throw FileError(pattern, "pattern matches no file");
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::string> directory_scans(const std::string& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    if (format_from_extension(e.path().string()) == SurfaceFormat::Auto) continue;
    if (e.path().extension() == ".json") continue;  // npy sidecars
    out.push_back(e.path().string());
  }
  if (out.empty()) throw FileError(dir, "directory holds no scan file with a known extension");
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::string> manifest_scans(const std::string& manifest) {
  require_regular_file(manifest);  // a FIFO would block
  std::ifstream in(manifest);
  if (!in) throw FileError(manifest, "cannot open manifest");
  fs::path base = fs::path(manifest).parent_path();
  std::vector<std::string> out;
  std::string line;
  while (std::getline(in, line)) {
    auto b = line.find_first_not_of(" \t\r");
    if (b == std::string::npos || line[b] == '#') continue;
    auto e = line.find_last_not_of(" \t\r");
    fs::path p = line.substr(b, e - b + 1);
    out.push_back(p.is_absolute() ? p.string() : (base / p).string());
  }
  if (out.empty()) throw FileError(manifest, "manifest lists no scan");
  return out;
}

}  // namespace

std::vector<std::string> expand_scan_inputs(const std::vector<std::string>& inputs) {
  std::vector<std::string> out;
  for (const auto& in : inputs) {
    std::vector<std::string> add;
    if (!in.empty() && in[0] == '@') {
      add = manifest_scans(in.substr(1));
    } else if (fs::is_directory(in)) {
      add = directory_scans(in);
    } else if (!fs::exists(in) && has_glob_chars(in)) {
      add = glob_files(in);
    } else {
      add = {in};
    }
    out.insert(out.end(), add.begin(), add.end());
  }
  return out;
}

void for_each_scan(const std::vector<std::string>& paths, const ReadOptions& options,
                   const std::function<void(std::size_t, const std::string&, Surface&)>& fn) {
  for (std::size_t i = 0; i < paths.size(); ++i) {
    Surface s = read_surface(paths[i], options);  // freed before the next is read
    fn(i, paths[i], s);
  }
}

WorkStats distribute_scans(
    const std::vector<std::string>& paths, const ReadOptions& options,
    const std::function<WorkResult(std::size_t, const std::string&, Surface&)>& compute,
    const std::function<void(std::size_t, WorkResult&&)>& consume,
    const DistributeOptions& distribute_options) {
  return distribute(
      paths.size(),
      [&](std::size_t i) {
        Surface s = read_surface(paths[i], options);  // freed when the item is done
        return compute(i, paths[i], s);
      },
      consume, distribute_options);
}

}  // namespace microbrdf
