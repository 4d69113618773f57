#include "microbrdf/atomic_file.hpp"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>

#include "microbrdf/error.hpp"
#include "microbrdf/file_size_limit.hpp"
#include "microbrdf/interrupt.hpp"
#include "microbrdf/run_inputs.hpp"

namespace microbrdf {

namespace {
std::atomic<unsigned> g_counter{0};
std::atomic<OutputGroup*> g_group{nullptr};
std::mutex g_group_mutex;

void remove_temporary(const std::string& temp) {
  std::error_code ec;
  std::filesystem::remove(temp, ec);
  unregister_temporary(temp);
}
}  // namespace

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  temp_ = path_ + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(g_counter++);
  register_temporary(temp_);
}

AtomicFile::~AtomicFile() {
  if (!committed_) remove_temporary(temp_);
}

void AtomicFile::commit() {
  // A write of this process was cut short by the file-size limit: whatever the writer did with
  // the error, this output may be truncated.
  if (file_size_limit_reached()) {
    remove_temporary(temp_);
    throw FileError(path_, file_size_limit_problem());
  }
  {
    std::lock_guard lock(g_group_mutex);
    if (OutputGroup* g = g_group.load()) {
      g->adopt(temp_, path_);
      committed_ = true;
      return;
    }
  }
  refuse_replacing_input(path_);  // the destructor removes the temporary
  without_interrupts([&] {
    if (std::rename(temp_.c_str(), path_.c_str()) != 0) {
      std::string why = std::strerror(errno);
      remove_temporary(temp_);
      throw FileError(path_, "cannot write: " + why);
    }
    unregister_temporary(temp_);
  });
  committed_ = true;
}

OutputGroup::OutputGroup() {
  std::lock_guard lock(g_group_mutex);
  g_group.store(this);
}

OutputGroup::~OutputGroup() {
  {
    std::lock_guard lock(g_group_mutex);
    if (g_group.load() == this) g_group.store(nullptr);
  }
  if (!done_)
    for (const auto& [temp, path] : staged_) remove_temporary(temp);
}

void OutputGroup::adopt(const std::string& temp, const std::string& path) {
  staged_.emplace_back(temp, path);
}

void OutputGroup::commit() {
  // Before any rename: an output that would replace an input refuses the whole group.
  for (const auto& staged : staged_) refuse_replacing_input(staged.second);
  {
    std::lock_guard lock(g_group_mutex);
    if (g_group.load() == this) g_group.store(nullptr);
  }
  done_ = true;
  if (file_size_limit_reached() && !staged_.empty()) {
    for (const auto& staged : staged_) remove_temporary(staged.first);
    throw FileError(staged_.front().second, file_size_limit_problem());
  }
  without_interrupts([&] {
    for (std::size_t i = 0; i < staged_.size(); ++i) {
      const auto& [temp, path] = staged_[i];
      if (std::rename(temp.c_str(), path.c_str()) != 0) {
        const std::string why = std::strerror(errno);
        for (std::size_t k = i; k < staged_.size(); ++k) remove_temporary(staged_[k].first);
        throw FileError(path, "cannot write: " + why);
      }
      unregister_temporary(temp);
    }
  });
}

OutputGroup::Bypass::Bypass() {
  std::lock_guard lock(g_group_mutex);
  saved_ = g_group.exchange(nullptr);
}

OutputGroup::Bypass::~Bypass() {
  std::lock_guard lock(g_group_mutex);
  g_group.store(saved_);
}

void write_file_atomic(const std::string& path, std::span<const std::uint8_t> bytes) {
  AtomicFile f(path);
  {
    std::ofstream out(f.temp_path(), std::ios::binary | std::ios::trunc);
    if (!out) throw FileError(path, std::string("cannot create: ") + std::strerror(errno));
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
    out.flush();
    if (!out) throw FileError(path, write_failure_problem(errno));
  }
  f.commit();
}

void write_file_atomic(const std::string& path, const std::string& text) {
  write_file_atomic(path, std::span<const std::uint8_t>(
                              reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

}  // namespace microbrdf
