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

}  // namespace microbrdf
