#pragma once
// Reading and writing tabulated NDFs (previews: ndf_preview.hpp; sampling: ndf_sampler.hpp;
// instrument convolution: ndf_convolve.hpp).

#include <string>
#include <vector>

#include "microbrdf/tabulated_ndf.hpp"

namespace microbrdf {

/// Writes the table: ".npy" (float64 N x N, row iy, numpy-readable as is) plus a JSON sidecar
/// with the same stem holding NdfMetadata and the conventions; ".exr" (single float channel
/// "D", metadata as string/float attributes). Atomic. Values are non-negative or NaN (NaN =
/// unmeasured, as in effective NDFs from measured BRDFs); infinities are refused. Throws FileError.
void write_ndf(const TabulatedNdf& ndf, const std::string& path);
/// Reads what write_ndf wrote (npy + optional sidecar, or exr). Throws FileError. For a stack
/// (write_ndf_stack) this is its primary table.
TabulatedNdf read_ndf(const std::string& path);

/// Writes a stack of tables of one resolution at increasing lambda_q (meta.wavelength_m), e.g.
/// the D_K of `ndf --method kirchhoff` over lambda_q: ".npy" holds a float64 array of shape
/// (layers, N, N) and the sidecar the metadata of layers[primary] plus "stack" {"wavelengths_q_m",
/// "primary", "notes"}; read_ndf then reads the primary table. ".exr" holds one table: only
/// layers[primary] is written and false is returned (the caller warns). One layer = write_ndf.
/// Atomic. Throws FileError.
bool write_ndf_stack(const std::vector<TabulatedNdf>& layers, std::size_t primary,
                     const std::string& path);
/// How many tables the file holds, from its sidecar alone (1 for a plain table or an .exr):
/// cheap, for callers that only need to know whether a file is a stack. Throws FileError.
std::size_t ndf_file_layers(const std::string& path);
/// Every table of the file, sorted by lambda_q (one for a 2-D .npy or an .exr). Throws FileError.
std::vector<TabulatedNdf> read_ndf_stack(const std::string& path);

}  // namespace microbrdf
