#include "microbrdf/run_inputs.hpp"

#include <sys/stat.h>

#include <filesystem>
#include <mutex>
#include <vector>

#include "microbrdf/error.hpp"

namespace microbrdf {
namespace {

struct Input {
  dev_t dev;
  ino_t ino;
  std::string path;  // as the reader named it, for the message
};

std::mutex g_mutex;
bool g_open = false;
std::vector<Input> g_inputs;

// The recorded input that is the same file as `path` (stat follows symbolic links), if any.
const Input* find_input(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return nullptr;
  for (const auto& in : g_inputs)
    if (in.dev == st.st_dev && in.ino == st.st_ino) return &in;
  return nullptr;
}

[[noreturn]] void refuse(const std::string& target, const Input& in, bool folder = false) {
  const std::string what = folder              ? "holds the input " + in.path + " of this run"
                           : in.path == target ? std::string("is an input of this run")
                                               : "is the input " + in.path + " of this run";
  throw FileError(target, what + ": the output would replace it; choose another output name");
}

}  // namespace

RunInputs::RunInputs() {
  std::lock_guard lock(g_mutex);
  owner_ = !g_open;
  g_open = true;
}

RunInputs::~RunInputs() {
  if (!owner_) return;
  std::lock_guard lock(g_mutex);
  g_open = false;
  g_inputs.clear();
}

void record_input(const std::string& path) {
  std::lock_guard lock(g_mutex);
  if (!g_open) return;
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || find_input(path)) return;
  g_inputs.push_back({st.st_dev, st.st_ino, path});
}

void refuse_replacing_input(const std::string& target) {
  std::lock_guard lock(g_mutex);
  if (!g_open) return;
  if (const Input* in = find_input(target)) refuse(target, *in);
}

void refuse_replacing_inputs_under(const std::string& dir) {
  namespace fs = std::filesystem;
  std::lock_guard lock(g_mutex);
  if (!g_open || g_inputs.empty()) return;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    if (const Input* in = find_input(dir)) refuse(dir, *in);
    return;
  }
  // The folder's own files (symbolic links not followed into other folders), by inode.
  for (auto it =
           fs::recursive_directory_iterator(dir, fs::directory_options::skip_permission_denied, ec);
       !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
    if (!it->is_symlink(ec) && it->is_regular_file(ec))
      if (const Input* in = find_input(it->path().string())) refuse(dir, *in, true);
}

}  // namespace microbrdf
