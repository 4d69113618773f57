#pragma once
// Error types. Every message a user sees names the file (when there is one) and what is wrong.

#include <new>
#include <stdexcept>
#include <string>
#include <utility>

namespace microbrdf {

/// Bad user input that is not a file: a malformed unit, an out-of-range parameter.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A file that cannot be read or written, or whose content is corrupt, truncated or hostile.
/// what() is "<path>: <problem>".
class FileError : public std::runtime_error {
 public:
  FileError(const std::string& path, const std::string& problem)
      : std::runtime_error(path + ": " + problem), path_(path), problem_(problem) {}
  /// An input file that is not there ("no such file", plus `detail`): the CLI's usage error
  /// (exit 2), unlike a file that cannot be read or written (exit 1).
  static FileError missing(const std::string& path, const std::string& detail = "") {
    FileError e(path, "no such file" + (detail.empty() ? "" : " (" + detail + ")"));
    e.missing_ = true;
    return e;
  }
  const std::string& path() const { return path_; }
  const std::string& problem() const { return problem_; }
  bool is_missing() const { return missing_; }

 private:
  std::string path_;
  std::string problem_;
  bool missing_ = false;
};

/// Memory or address space ran out where the memory budget could not be checked first (in a
/// library that allocates by itself, such as Embree). what() says what needed it and the
/// limit; it is a std::bad_alloc for code that catches those.
class OutOfMemory : public std::bad_alloc {
 public:
  explicit OutOfMemory(std::string message) : message_(std::move(message)) {}
  const char* what() const noexcept override { return message_.c_str(); }

 private:
  std::string message_;
};

/// Runs `f` on the data of the file at `path`: an InputError it raises (a property of that
/// data: too few valid samples, no normal, no mass) becomes FileError(path, message), so the
/// user learns which file it is about.
template <class F>
auto about_file(const std::string& path, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const InputError& e) {
    throw FileError(path, e.what());
  }
}

}  // namespace microbrdf
