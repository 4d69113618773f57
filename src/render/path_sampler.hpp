#pragma once
// The random numbers of one camera path (render.cpp), from one of two samplers:
//
// - Sobol (default): a padded, Owen-scrambled Sobol' sampler. Every 1D or 2D request of a path
//   (pixel jitter, hero wavelength, light sample, BRDF sample, Russian roulette) takes the first
//   one or two dimensions of the Sobol' sequence (van der Corput and its (0,2)-partner, whose
//   first 2^m points form a (0,m,2)-net) at a sample index shuffled per (pixel, dimension), with
//   a nested uniform (Owen) scramble seeded per (pixel, dimension); shuffled indices stay in
//   [0, 2^m) with 2^m >= spp, the first block of 2^m points. For spp = 2^m the spp
//   points of every 2D request of a pixel fall one into each elementary interval of area 2^-m
//   (stratified in every aspect ratio), every 1D request one into each of spp equal intervals,
//   while distinct requests stay independent. Each value is uniform on [0,1) on its own, so the
//   estimator stays unbiased; for other spp the points are a random subset of the next
//   power-of-two net (still unbiased, less stratified).
// - Independent: a counter-based hash per (seed, pixel, sample, dimension): plain Monte Carlo,
//   kept as the reference the variance figures are measured against.
//
// Both are pure functions of (seed, pixel, sample index, request number), so an image does not
// depend on the thread count. The scramble works on bit-reversed values, where a nested
// uniform scramble is any bijection whose bit k depends only on bits 0..k (a "T-function": sums,
// products by odd numbers, x ^ (x times an even number)); the index shuffle is a T-function on
// the index itself, which permutes every range [0, 2^m).
#include <array>
#include <cstdint>

#include "core/splitmix64.hpp"

namespace microbrdf::pt {

namespace detail {
// Second Sobol' dimension by its definition (see PathSampler::sobol_dim1) and its byte tables.
constexpr std::uint32_t sobol_dim1_loop(std::uint32_t index) {
  std::uint32_t v = 0x80000000u, r = 0;
  for (; index; index >>= 1, v ^= v >> 1)
    if (index & 1) r ^= v;
  return r;
}
constexpr std::uint32_t reverse_bits_loop(std::uint32_t x) {
  std::uint32_t r = 0;
  for (int k = 0; k < 32; ++k) r |= ((x >> k) & 1u) << (31 - k);
  return r;
}
// reversed: the entries' bits in reverse order (reversal is linear over XOR, so the XOR of the
// reversed entries is the reversed value).
constexpr std::array<std::array<std::uint32_t, 256>, 4> sobol_dim1_tables(bool reversed) {
  std::array<std::array<std::uint32_t, 256>, 4> t{};
  for (int b = 0; b < 4; ++b)
    for (std::uint32_t x = 0; x < 256; ++x) {
      const std::uint32_t v = sobol_dim1_loop(x << (8 * b));
      t[b][x] = reversed ? reverse_bits_loop(v) : v;
    }
  return t;
}
inline constexpr auto kSobolDim1Tables = sobol_dim1_tables(false);
inline constexpr auto kSobolDim1ReversedTables = sobol_dim1_tables(true);
}  // namespace detail

enum class PathSamplerKind { Sobol, Independent };

/// The hashes of a pixel's requests, the same for all of its samples (they depend on the seed,
/// the pixel and the request number only): made on first use and shared by the PathSamplers of
/// the pixel's samples, which one thread traces in turn. Saves two of the three 64-bit hashes
/// of a 2D request, which otherwise head its chain of dependent operations.
class PixelHashes {
 public:
  PixelHashes(std::uint64_t seed, std::uint64_t pixel)
      : key_(microbrdf::detail::splitmix64(
            microbrdf::detail::splitmix64(seed * 0xD1B54A32D192ED03ull + 1) ^ pixel)) {}
  std::uint64_t key() const { return key_; }
  /// The hash of request r (1, 2, ...) and, for 2D requests, that of its second coordinate.
  std::uint64_t first(std::uint64_t r) {
    if (r >= kCached) return hash(r);
    if (!(have_ >> r & 1)) {
      h_[r] = hash(r);
      h2_[r] = microbrdf::detail::splitmix64(h_[r] + 1);
      have_ |= std::uint64_t(1) << r;
    }
    return h_[r];
  }
  std::uint64_t second(std::uint64_t r) const {  // (after first(r))
    return r >= kCached ? microbrdf::detail::splitmix64(hash(r) + 1) : h2_[r];
  }

 private:
  static constexpr std::uint64_t kCached = 64;
  std::uint64_t hash(std::uint64_t r) const {
    return microbrdf::detail::splitmix64(key_ ^ (0x9E3779B97F4A7C15ull * r));
  }
  std::uint64_t key_;
  std::uint64_t have_ = 0;  // bit r: h_[r], h2_[r] are set
  std::uint64_t h_[kCached], h2_[kCached];
};

class PathSampler {
 public:
  /// `sample` in [0, spp): the index of this path among the pixel's spp samples.
  PathSampler(PathSamplerKind kind, std::uint64_t seed, std::uint64_t pixel, std::uint32_t sample,
              std::uint32_t spp)
      : kind_(kind),
        key_(mix(mix(seed * 0xD1B54A32D192ED03ull + 1) ^ pixel)),
        sample_(sample),
        bits_(index_bits(spp)) {}
  /// The same numbers, with the pixel's request hashes shared with its other samples
  /// (`hashes` made for the same seed and pixel; it must outlive the sampler).
  PathSampler(PathSamplerKind kind, PixelHashes& hashes, std::uint32_t sample, std::uint32_t spp)
      : kind_(kind),
        key_(hashes.key()),
        sample_(sample),
        bits_(index_bits(spp)),
        hashes_(&hashes) {}

  /// One uniform in [0,1).
  double get1d() {
    const std::uint64_t h = hash(++request_);
    if (kind_ == PathSamplerKind::Independent)
      return to_unit(std::uint32_t(mix(h ^ (std::uint64_t(sample_) << 32))));
    const std::uint32_t i = shuffle(sample_, std::uint32_t(h >> 32), bits_);
    return to_unit(owen_of_reversed(i, std::uint32_t(h)));
  }

  /// Two uniforms in [0,1)^2 (one 2D request: stratified jointly).
  void get2d(double& u1, double& u2) {
    const std::uint64_t h = hash(++request_);
    if (kind_ == PathSamplerKind::Independent) {
      const std::uint64_t r = mix(h ^ (std::uint64_t(sample_) << 32));
      u1 = to_unit(std::uint32_t(r));
      u2 = to_unit(std::uint32_t(r >> 32));
      return;
    }
    const std::uint32_t i = shuffle(sample_, std::uint32_t(h >> 32), bits_);
    const std::uint64_t h2 = hashes_ ? hashes_->second(request_) : mix(h + 1);
    u1 = to_unit(owen_of_reversed(i, std::uint32_t(h)));
    // owen(sobol_dim1(i), h2) with the first reversal in the tables
    u2 = to_unit(reverse_bits(t_function(sobol_dim1_reversed(i), std::uint32_t(h2))));
  }

  // Exposed for the tests.
  static std::uint32_t reverse_bits(std::uint32_t x) {
    x = __builtin_bswap32(x);  // the bytes in reverse order, then the bits within each byte
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    return ((x >> 4) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4);
  }
  /// Second Sobol' dimension (primitive polynomial x + 1): direction numbers
  /// v_0 = 2^31, v_k = v_{k-1} ^ (v_{k-1} >> 1); the value is the XOR of v_k over the set bits k
  /// of the index (Bratley & Fox's construction, generator matrix = Pascal's triangle mod 2).
  static constexpr std::uint32_t sobol_dim1_loop(std::uint32_t index) {
    return detail::sobol_dim1_loop(index);
  }
  /// The same from four tables of 256 entries, one per index byte (the value is linear in the
  /// index bits over GF(2)): no loop with a branch per index bit.
  static std::uint32_t sobol_dim1(std::uint32_t index) {
    const auto& t = detail::kSobolDim1Tables;
    return t[0][index & 255u] ^ t[1][(index >> 8) & 255u] ^ t[2][(index >> 16) & 255u] ^
           t[3][index >> 24];
  }
  /// reverse_bits(sobol_dim1(index)), from tables of reversed entries.
  static std::uint32_t sobol_dim1_reversed(std::uint32_t index) {
    const auto& t = detail::kSobolDim1ReversedTables;
    return t[0][index & 255u] ^ t[1][(index >> 8) & 255u] ^ t[2][(index >> 16) & 255u] ^
           t[3][index >> 24];
  }
  /// Nested uniform scramble of a 32-bit binary fraction (most significant bit first).
  static std::uint32_t owen(std::uint32_t x, std::uint32_t seed) {
    return reverse_bits(t_function(reverse_bits(x), seed));
  }
  /// owen(reverse_bits(i), seed) (the van der Corput value of index i, scrambled) without the
  /// two reversals that cancel.
  static std::uint32_t owen_of_reversed(std::uint32_t i, std::uint32_t seed) {
    return reverse_bits(t_function(i, seed));
  }
  /// A permutation of [0, 2^m) chosen by `seed`: a nested scramble of the m index bits taken
  /// from the most significant one down (bit-reversed T-function), so that the low index bits,
  /// which pick the leading digits of the van der Corput and Sobol' values, are random functions
  /// of all the index bits. (A T-function on the index itself would keep the lowest bit as
  /// i_0 XOR a constant in every request: the first digit of every request would then be the
  /// same up to a flip, and the requests of a pixel strongly correlated.)
  static std::uint32_t shuffle(std::uint32_t i, std::uint32_t seed, int m) {
    if (m == 0) return 0;
    const std::uint32_t r = reverse_bits(i) >> (32 - m);  // m-bit reversal
    const std::uint32_t t = t_function(r, seed) & ((m == 32 ? 0u : (1u << m)) - 1u);
    return reverse_bits(t) >> (32 - m);
  }

 private:
  static std::uint32_t t_function(std::uint32_t x, std::uint32_t seed) {
    x += seed;
    x ^= x * 0x3A4C2B16u;   // even: bit k of the product depends on bits < k
    x *= (seed >> 1) | 1u;  // odd: bit k = x_k ^ f(bits < k)
    x ^= x * 0x7F1D5C94u;
    x += seed >> 7;
    x *= 0x2545F491u;
    x ^= x * 0x51ED270Au;
    return x;
  }
  static std::uint64_t mix(std::uint64_t z) { return microbrdf::detail::splitmix64(z); }
  std::uint64_t hash(std::uint64_t r) const {
    return hashes_ ? hashes_->first(r) : mix(key_ ^ (0x9E3779B97F4A7C15ull * r));
  }
  static double to_unit(std::uint32_t x) { return double(x) * 0x1.0p-32; }
  // m for the smallest 2^m >= spp: the shuffled indices stay inside the first block of 2^m
  // points, which is a (0,m,2)-net (an index bit k moves the leading output bits of the second
  // dimension up to bit k + 1, so indices from different blocks would break the net).
  static int index_bits(std::uint32_t spp) {
    int m = 0;
    while (m < 31 && (1u << m) < spp) ++m;
    return m;
  }

  PathSamplerKind kind_;
  std::uint64_t key_;
  std::uint32_t sample_;
  int bits_;
  std::uint64_t request_ = 0;
  PixelHashes* hashes_ = nullptr;
};

}  // namespace microbrdf::pt
