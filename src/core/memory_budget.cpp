#include "microbrdf/memory_budget.hpp"

#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>

#include "microbrdf/error.hpp"

namespace microbrdf {

namespace {

constexpr std::uint64_t kExpansionFactor = 64;
constexpr std::uint64_t kExpansionFloor = std::uint64_t{256} << 20;

std::uint64_t half_physical_memory() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page <= 0) return std::uint64_t{4} << 30;
  return mul_sat(static_cast<std::uint64_t>(pages), static_cast<std::uint64_t>(page)) / 2;
}

std::atomic<std::uint64_t> g_budget{0};  // 0: not yet computed
std::atomic<bool> g_explicit{false};

std::string budget_hint() {
  return memory_budget_is_explicit() ? " (--max-memory)"
                                     : " (half the physical memory; --max-memory to change)";
}

}  // namespace

std::uint64_t mul_sat(std::uint64_t a, std::uint64_t b) {
  if (a != 0 && b > std::numeric_limits<std::uint64_t>::max() / a)
    return std::numeric_limits<std::uint64_t>::max();
  return a * b;
}

std::uint64_t memory_budget() {
  std::uint64_t b = g_budget.load();
  if (b == 0) {
    b = half_physical_memory();
    g_budget.store(b);
  }
  return b;
}

void set_memory_budget(std::uint64_t bytes) {
  if (bytes == 0) throw InputError("--max-memory must be positive");
  g_budget.store(bytes);
  g_explicit.store(true);
}

bool memory_budget_is_explicit() { return g_explicit.load(); }

std::uint64_t parse_byte_size(const std::string& text) {
  const std::string why = "'" + text + "' is not a size (give bytes or 512M, 2G, 1.5GiB)";
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    throw InputError(why);
  }
  std::string unit = text.substr(used);
  if (!unit.empty() && unit.front() == ' ') unit.erase(0, 1);
  double scale = 1;
  if (unit.empty() || unit == "B")
    scale = 1;
  else if (unit == "K" || unit == "KB" || unit == "KiB" || unit == "k")
    scale = 1024.0;
  else if (unit == "M" || unit == "MB" || unit == "MiB")
    scale = 1024.0 * 1024;
  else if (unit == "G" || unit == "GB" || unit == "GiB")
    scale = 1024.0 * 1024 * 1024;
  else if (unit == "T" || unit == "TB" || unit == "TiB")
    scale = 1024.0 * 1024 * 1024 * 1024;
  else
    throw InputError(why);
  const double bytes = v * scale;
  if (!std::isfinite(bytes) || !(bytes >= 1) || bytes > 1.8e19) throw InputError(why);
  return static_cast<std::uint64_t>(bytes);
}

std::string format_bytes(std::uint64_t bytes) {
  char buf[64];
  const double b = static_cast<double>(bytes);
  if (bytes >= (std::uint64_t{1} << 40))
    std::snprintf(buf, sizeof buf, "%.1f TiB", b / std::ldexp(1.0, 40));
  else if (bytes >= (std::uint64_t{1} << 30))
    std::snprintf(buf, sizeof buf, "%.1f GiB", b / std::ldexp(1.0, 30));
  else if (bytes >= (std::uint64_t{1} << 20))
    std::snprintf(buf, sizeof buf, "%.0f MiB", b / std::ldexp(1.0, 20));
  else
    std::snprintf(buf, sizeof buf, "%llu bytes", static_cast<unsigned long long>(bytes));
  return buf;
}

void check_memory(const std::string& file, std::uint64_t bytes, const std::string& what) {
  if (bytes > memory_budget())
    throw FileError(file, "needs " + format_bytes(bytes) + " for " + what +
                              ", over the memory budget of " + format_bytes(memory_budget()) +
                              budget_hint());
}

void check_expansion(const std::string& file, std::uint64_t file_bytes, std::uint64_t bytes,
                     const std::string& what) {
  check_memory(file, bytes, what);
  if (memory_budget_is_explicit()) return;
  const std::uint64_t allowed = std::max(kExpansionFloor, mul_sat(file_bytes, kExpansionFactor));
  if (bytes > allowed)
    throw FileError(file, "a file of " + format_bytes(file_bytes) + " asks for " +
                              format_bytes(bytes) + " for " + what +
                              " (more than 64 times its size: a decompression bomb or a "
                              "corrupt header?); pass --max-memory to allow it");
}

}  // namespace microbrdf
