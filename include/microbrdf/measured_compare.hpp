#pragma once
// Predicted NDFs against an effective NDF inferred from measurements (Dong 2015 section 7,
// Figs. 8-9; docs/measured.md): the prediction is convolved with the instrument signature (an
// angular Gaussian of the given FWHM, or a measured signature such as a mirror's effective NDF),
// brought to the measured table's nodes (bilinear), and compared on the measured nodes only
// (NaN nodes of the measured table are skipped):
//  - scale: the least-squares factor k of k P against M (the measured table keeps the BRDF's
//    absolute scale, which carries the Fresnel term's uncertainty);
//  - relative_l2 = ||M - k P|| / ||M||;
//  - hellinger: both restricted to the measured nodes and normalised there,
//    sqrt(1/2 sum (sqrt m - sqrt p)^2) in [0, 1];
//  - width ratios: GGX fits of both tables (alpha_x, alpha_y), predicted / measured.

#include <cstddef>

#include "microbrdf/fit.hpp"
#include "microbrdf/tabulated_ndf.hpp"

namespace microbrdf {

struct NdfComparison {
  std::size_t nodes = 0;  ///< measured nodes compared
  double scale = 1, relative_l2 = 0, hellinger = 0;
  FitResult measured_fit, predicted_fit;
  double alpha_x_ratio = 1, alpha_y_ratio = 1;  ///< predicted / measured
};

/// `instrument_fwhm_rad` > 0 convolves the prediction with that Gaussian first; `instrument`
/// (if not null) convolves it with that measured signature instead (normalised, centred on the
/// pole). Throws InputError when the measured table has no measured node.
NdfComparison compare_ndfs(const TabulatedNdf& measured, const TabulatedNdf& predicted,
                           double instrument_fwhm_rad = 0,
                           const TabulatedNdf* instrument = nullptr);

/// The prediction as compared: convolved with the instrument and sampled at the measured nodes
/// (0 outside the disk).
TabulatedNdf instrument_view(const TabulatedNdf& predicted, std::size_t resolution,
                             double instrument_fwhm_rad, const TabulatedNdf* instrument);

}  // namespace microbrdf
