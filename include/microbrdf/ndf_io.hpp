#pragma once
// Reading and writing tabulated NDFs (previews: ndf_preview.hpp; sampling: ndf_sampler.hpp;
// instrument convolution: ndf_convolve.hpp).

#include <string>

#include "microbrdf/tabulated_ndf.hpp"

namespace microbrdf {

/// Writes the table: ".npy" (float64 N x N, row iy, numpy-readable as is) plus a JSON sidecar
/// with the same stem holding NdfMetadata and the conventions; ".exr" (single float channel
/// "D", metadata as string/float attributes). Atomic. Values are non-negative or NaN (NaN =
/// unmeasured, as in effective NDFs from measured BRDFs); infinities are refused. Throws FileError.
void write_ndf(const TabulatedNdf& ndf, const std::string& path);
/// Reads what write_ndf wrote (npy + optional sidecar, or exr). Throws FileError.
TabulatedNdf read_ndf(const std::string& path);

}  // namespace microbrdf
