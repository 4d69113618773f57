#pragma once
// The memory budget: how many bytes one input (a scan, a scene, a texture) may make the tool
// allocate. Readers ask before they allocate, with the size they will need, so a small
// hostile file is refused with a message instead of growing to gigabytes.
//
// Two rules:
//  - a global cap, by default half of the physical memory (`--max-memory` changes it);
//  - while the cap is the default, what a file expands to (decompressed payloads, sample
//    arrays, document trees) is also bounded by what it holds: at most 64 times its size on
//    disk, or 256 MiB, whichever is larger. A legitimate scan is stored at a few bytes per
//    sample; a file of a few kilobytes that asks for gigabytes is a decompression bomb or a
//    lie in a header. Setting `--max-memory` explicitly lifts this second rule.
#include <cstdint>
#include <string>

namespace microbrdf {

/// The global cap in bytes.
std::uint64_t memory_budget();
/// Sets the global cap (`--max-memory`); from then on only the cap applies.
void set_memory_budget(std::uint64_t bytes);
/// Whether the cap was set explicitly.
bool memory_budget_is_explicit();

/// "512M", "2G", "1.5GiB", "100000000" (bytes; K/M/G/T are powers of 1024). Throws InputError.
std::uint64_t parse_byte_size(const std::string& text);
/// "1.5 GiB", "312 MiB", "900 bytes".
std::string format_bytes(std::uint64_t bytes);

/// Throws FileError("<file>: needs <bytes> for <what>, over the memory budget of ... ") when
/// `bytes` exceeds the global cap.
void check_memory(const std::string& file, std::uint64_t bytes, const std::string& what);

/// check_memory, plus the expansion rule for a file of `file_bytes` bytes on disk.
void check_expansion(const std::string& file, std::uint64_t file_bytes, std::uint64_t bytes,
                     const std::string& what);

/// a * b, saturating at UINT64_MAX (sizes computed from header fields never wrap).
std::uint64_t mul_sat(std::uint64_t a, std::uint64_t b);

}  // namespace microbrdf
