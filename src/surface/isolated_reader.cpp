#include "surface/isolated_reader.hpp"

#include <poll.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "microbrdf/error.hpp"
#include "microbrdf/interrupt.hpp"

// ASan reserves terabytes of address space for its shadow memory: no RLIMIT_AS under it.
#if defined(__SANITIZE_ADDRESS__)
#define MICROBRDF_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define MICROBRDF_ASAN 1
#endif
#endif

namespace microbrdf::detail {
namespace {

// --- a minimal wire format for a Surface (same machine, same build: native byte order) ---
struct Writer {
  std::vector<std::uint8_t> buf;
  template <class T>
  void pod(const T& v) {
    const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
    buf.insert(buf.end(), p, p + sizeof(T));
  }
  void str(const std::string& s) {
    pod<std::uint64_t>(s.size());
    buf.insert(buf.end(), s.begin(), s.end());
  }
  template <class T>
  void vec(const std::vector<T>& v) {
    pod<std::uint64_t>(v.size());
    const auto* p = reinterpret_cast<const std::uint8_t*>(v.data());
    buf.insert(buf.end(), p, p + v.size() * sizeof(T));
  }
};

struct Reader {
  const std::vector<std::uint8_t>& buf;
  std::size_t pos = 0;
  void need(std::size_t n) {
    if (n > buf.size() - pos) throw std::runtime_error("isolated reader: short message from child");
  }
  template <class T>
  T pod() {
    need(sizeof(T));
    T v;
    std::memcpy(&v, buf.data() + pos, sizeof(T));
    pos += sizeof(T);
    return v;
  }
  std::string str() {
    auto n = pod<std::uint64_t>();
    need(n);
    std::string s(reinterpret_cast<const char*>(buf.data() + pos), n);
    pos += n;
    return s;
  }
  template <class T>
  std::vector<T> vec() {
    auto n = pod<std::uint64_t>();
    if (n > (buf.size() - pos) / sizeof(T))
      throw std::runtime_error("isolated reader: short message from child");
    std::vector<T> v(n);
    std::memcpy(v.data(), buf.data() + pos, n * sizeof(T));
    pos += n * sizeof(T);
    return v;
  }
};

void encode(Writer& w, const Surface& s) {
  w.pod<std::uint8_t>(1);  // ok
  w.pod<std::uint64_t>(s.nx);
  w.pod<std::uint64_t>(s.ny);
  for (double v : {s.dx, s.dy, s.x0, s.y0, s.z0}) w.pod(v);
  w.vec(s.z);
  w.vec(s.valid);
  const auto& m = s.meta;
  for (const auto* f : {&m.source_path, &m.format, &m.instrument, &m.date, &m.comment,
                        &m.z_unit_in_file, &m.leveling})
    w.str(*f);
  w.pod<std::uint64_t>(m.extra.size());
  for (const auto& [k, v] : m.extra) {
    w.str(k);
    w.str(v);
  }
}

Surface decode(Reader& r) {
  Surface s;
  s.nx = r.pod<std::uint64_t>();
  s.ny = r.pod<std::uint64_t>();
  for (double* v : {&s.dx, &s.dy, &s.x0, &s.y0, &s.z0}) *v = r.pod<double>();
  s.z = r.vec<double>();
  s.valid = r.vec<std::uint8_t>();
  auto& m = s.meta;
  for (auto* f : {&m.source_path, &m.format, &m.instrument, &m.date, &m.comment, &m.z_unit_in_file,
                  &m.leveling})
    *f = r.str();
  auto n = r.pod<std::uint64_t>();
  for (std::uint64_t i = 0; i < n; ++i) {
    auto k = r.str();
    m.extra.emplace_back(k, r.str());
  }
  return s;
}

void write_all(int fd, const std::vector<std::uint8_t>& b) {
  std::size_t off = 0;
  while (off < b.size()) {
    ssize_t n = ::write(fd, b.data() + off, b.size() - off);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    off += static_cast<std::size_t>(n);
  }
}

[[noreturn]] void child_main(int fd, const std::function<Surface()>& reader, unsigned timeout_s) {
  ::alarm(timeout_s);  // a hang ends as SIGALRM
#ifndef MICROBRDF_ASAN
  // Cap the address space so a runaway allocation fails instead of exhausting the machine.
  rlimit lim{std::uint64_t{16} << 30, std::uint64_t{16} << 30};
  ::setrlimit(RLIMIT_AS, &lim);
#endif
  Writer w;
  try {
    encode(w, reader());
  } catch (const FileError& e) {
    w.buf.clear();
    w.pod<std::uint8_t>(0);
    w.str(e.problem());
  } catch (const std::exception& e) {
    w.buf.clear();
    w.pod<std::uint8_t>(0);
    w.str(std::string("decoder failed: ") + e.what());
  }
  write_all(fd, w.buf);
  ::close(fd);
  ::_exit(0);  // no atexit handlers, no leak check of the library's leftovers
}

}  // namespace

Surface read_isolated(const std::string& name, const std::string& library,
                      const std::function<Surface()>& reader, unsigned timeout_s) {
  const char* off = std::getenv("MICROBRDF_NO_ISOLATION");
  if (off && *off && *off != '0') return reader();

  int fds[2];
  if (::pipe(fds) != 0)
    throw FileError(name, std::string("cannot create a pipe: ") + std::strerror(errno));
  pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    throw FileError(name, std::string("cannot fork a reader process: ") + std::strerror(errno));
  }
  if (pid == 0) {
    ::close(fds[0]);
    unblock_interrupts_in_child();  // the parent's watcher thread is not in the child
    child_main(fds[1], reader, timeout_s);
  }
  ::close(fds[1]);
  std::vector<std::uint8_t> msg;
  std::uint8_t chunk[1 << 16];
  while (true) {
    ssize_t n = ::read(fds[0], chunk, sizeof chunk);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    msg.insert(msg.end(), chunk, chunk + n);
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFSIGNALED(status)) {
    int sig = WTERMSIG(status);
    throw FileError(
        name, library +
                  (sig == SIGALRM ? " did not finish decoding this file within " +
                                        std::to_string(timeout_s) + " s"
                                  : " crashed decoding this file (signal " + std::to_string(sig) +
                                        ": " + strsignal(sig) + ")") +
                  "; the file is corrupt or uses a feature it cannot handle");
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || msg.empty()) {
    // Under a sanitizer a crash in the child ends as exit code 1 rather than a signal.
    throw FileError(name, library + " crashed or failed decoding this file (reader process exit " +
                              std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) +
                              "); the file is corrupt or uses a feature it cannot handle");
  }
  Reader r{msg};
  if (r.pod<std::uint8_t>() == 0) throw FileError(name, r.str());
  return decode(r);
}

}  // namespace microbrdf::detail
