#pragma once
// Pieces of the separable Fourier texture synthesis, exposed for tests and benchmarks.
#include <complex>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace microbrdf::detail {

/// The exemplar band (bin spacings 1/(n pitch); band j = [j - 1/2, j + 1/2)) that output bin k
/// of an m-bin line at pitch_out falls in (exact integer arithmetic when the pitches agree).
std::size_t exemplar_band(std::size_t k, std::size_t n, double pitch, std::size_t m,
                          double pitch_out);

/// Resamples an exemplar's one-sided line spectrum P (line_power_spectrum: bins k/(n pitch)) to
/// the m/2 + 1 bins k/(m pitch_out) of the output, band-preserving: the power p[j] of exemplar
/// band j >= 1 is shared evenly by the output bins that fall in it (exemplar_band), so every
/// band keeps its power exactly; a band no bin falls in (output coarser in frequency) goes to the
/// nearest bin. Band 0 (the mean) and frequencies beyond the exemplar's Nyquist frequency get
/// nothing: structure larger than the exemplar or finer than its texels is not invented.
std::vector<double> resample_line_spectrum(const std::vector<double>& p, std::size_t n,
                                           double pitch, std::size_t m, double pitch_out);

/// A real nx x ny field with the half-spectrum amplitudes amp[ky * (nx/2+1) + kx] and phases
/// uniformly random from (seed, stream) (Hermitian symmetry kept on the self-conjugate columns
/// kx = 0 and nx/2, whose entries ky and ny - ky share the modulus of the lower one),
/// by an inverse FFT (FFTW); direct = true evaluates the same sum as a naive 2-D inverse DFT
/// (the brute-force reference, O(N^2) per texel).
std::vector<double> random_phase_field(const std::vector<double>& amp, std::size_t nx,
                                       std::size_t ny, std::uint64_t seed, std::uint64_t stream,
                                       bool direct = false);

/// Half-spectrum amplitudes of the Gaussian field G whose exponential exp(G), with the log-normal
/// mean and variance given, has the power spectrum amp^2 (up to a constant): the correlation is
/// pre-distorted as rho_G = ln(1 + rho_L (e^{s^2} - 1)) / s^2, s^2 = ln(1 + variance / mean^2).
std::vector<double> lognormal_amplitudes(const std::vector<double>& amp, std::size_t nx,
                                         std::size_t ny, double mean, double variance);
/// Standardises f and maps it to exp(mu + s z) with the log-normal mean and variance given.
void to_lognormal(std::vector<double>& f, double mean, double variance);

/// Radially averaged power spectrum of an n x n field (mean removed): the mean of |X(k)|^2 / n^4
/// over the annulus round(|k|) = r (k in cycles per n texels), r = 1..n/2; entry 0 is 0 and
/// the corners beyond the Nyquist circle are left out.
std::vector<double> radial_power_spectrum(const std::vector<double>& v, std::size_t n);
/// The same from the half spectrum (fft2_r2c layout, unnormalised) of an n x n field.
std::vector<double> radial_power_spectrum(const std::vector<std::complex<double>>& spec,
                                          std::size_t n);
/// Relative L2 distance between two radial spectra, each normalised to unit total (the shape):
/// sqrt(sum (a - b)^2 / sum b^2).
double spectrum_distance(const std::vector<double>& a, const std::vector<double>& b);

/// n quantiles of the exemplar values (sorted; linear between order statistics, the ends held
/// at the minimum and maximum), entry r for the output rank r: every entry within
/// [min, max] of the values.
std::vector<float> quantile_table(std::vector<float> values, std::size_t n);
/// out[i] = q[rank of f[i]]: ranks of the values at float precision, ties in texel order (a stable
/// radix sort; deterministic). q must have f.size() entries.
void rank_remap(const std::vector<double>& f, const std::vector<float>& q, std::vector<float>& out);

}  // namespace microbrdf::detail
