// SplitMix64 (Steele, Lea, Flood 2014): the 64-bit mixing function used for counter-based,
// reproducible random streams across the library (one definition for every user).
#pragma once

#include <cstdint>

namespace microbrdf::detail {

inline std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

/// The seed of chunk (or row, or stream) `index` of a computation seeded with `seed`, for work
/// split into independent pieces whose results must not depend on how they are scheduled:
/// seed * 1000003 + index (1000003 is prime, so nearby seeds give disjoint chunk seeds).
inline std::uint64_t chunk_seed(std::uint64_t seed, std::uint64_t index) {
  return seed * 1000003ull + index;
}

}  // namespace microbrdf::detail
