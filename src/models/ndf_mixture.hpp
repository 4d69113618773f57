#pragma once
// Two-lobe NDFs: w D_a + (1 - w) D_b of any two registered models (ndf_model("mixture:a+b")).
#include <memory>

#include "microbrdf/ndf_model.hpp"

namespace microbrdf {

/// The mixture of `a` and `b` (both outlive it: registry entries). Parameters: a's prefixed
/// "lobe1.", b's prefixed "lobe2.", then "weight" (of lobe 1, in [0, 1]).
std::unique_ptr<NdfModel> make_mixture_model(const NdfModel& a, const NdfModel& b);

}  // namespace microbrdf
