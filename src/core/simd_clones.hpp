#pragma once
// MICROBRDF_SIMD_CLONES before a function whose loops are written for the compiler's vectoriser
// (GCC vector extensions or plain loops): on x86-64 GCC also builds an AVX2 version of it and
// picks one at run time. GCC's "avx2" target does not include FMA, so products and sums round
// exactly as in the baseline build and both versions give the same bits. Off under
// AddressSanitizer and with other compilers.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && \
    !defined(__SANITIZE_ADDRESS__)
#define MICROBRDF_SIMD_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define MICROBRDF_SIMD_CLONES
#endif
