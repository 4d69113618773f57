#pragma once
// Internal: the streaming filtered-normal pass behind filtered_normals() and the filtered NDF
// estimator, and the thread-count-independent splat (src/ndf/filtered_normals.cpp).

#include <cstddef>

#include "microbrdf/surface.hpp"
#include "microbrdf/tabulated_ndf.hpp"

namespace microbrdf::detail {

/// Filtered normal of every sample of `s` (row-major, nx * ny entries per array). Where a sample
/// is invalid or fails the support rule: mx = my = mz = 0 if `mz` is given, otherwise mx = NaN
/// (my untouched). Bit for bit the same whatever the thread count.
void filtered_normals_into(const Surface& s, double sigma, double truncate, double min_support,
                           double* mx, double* my, double* mz, std::size_t& used,
                           std::size_t& skipped);

/// t.splat(mx[i], my[i], weight) for every i in 0..n-1 with mx[i] not NaN, in that order (the
/// same table bit for bit as that loop, whatever `threads`: each thread owns a band of table
/// rows). mx and my are overwritten (with the splats' bilinear weights).
void splat_normals(double* mx, double* my, std::size_t n, double weight, TabulatedNdf& t,
                   int threads);

/// A buffer of at least `n` doubles owned by the calling thread and reused by later calls with
/// the same `slot` (0, 1 or 2): no fresh allocation (and no page faults) per scan.
double* thread_scratch(std::size_t n, int slot);

}  // namespace microbrdf::detail
