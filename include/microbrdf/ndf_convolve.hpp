#pragma once
// Instrument signatures applied to a tabulated NDF (what a gonioreflectometer would see).

#include "microbrdf/tabulated_ndf.hpp"

namespace microbrdf {

/// Convolves with an instrument signature: an angular Gaussian of full width at half maximum
/// `fwhm_rad` on the sphere (e.g. 1.5 deg, Dong section 7). Conserves integral D(m)(m.n) dw.
/// Each node's mass D_j Delta^2 is spread over the nodes within 4 sigma (angle) with weights
/// exp(-angle^2 / (2 sigma^2)) * (solid angle Delta^2 / m_z of the receiving node), normalised
/// per source node. Nodes on or outside the unit circle carry no mass. fwhm_rad <= 0 returns
/// the input unchanged. Cost ~ (pi/4) N^2 * pi (4 sigma / Delta)^2 kernel evaluations, twice.
TabulatedNdf convolve_angular_gaussian(const TabulatedNdf& ndf, double fwhm_rad);

/// Convolves with a measured signature S (an NDF table of a mirror's lobe about the pole,
/// resampled to the resolution of `ndf` and normalised): each node's mass is moved along S's
/// disk offsets (slope-offset approximation, exact to < 1e-4 relative for lobes ~1 deg wide).
/// Conserves the integral except for mass moved beyond the unit circle. Appends a note to
/// meta.notes. Throws InputError when S has no mass.
TabulatedNdf convolve_signature(const TabulatedNdf& ndf, const TabulatedNdf& signature);

/// The instrument signature of any NDF (naive, filtered, Kirchhoff D_K): the measured
/// `signature` if not null, else the Gaussian of `fwhm_rad` (0 = unchanged). Throws InputError
/// for a negative or non-finite FWHM, or when both are given.
TabulatedNdf apply_instrument(const TabulatedNdf& ndf, double fwhm_rad,
                              const TabulatedNdf* signature = nullptr);

}  // namespace microbrdf
