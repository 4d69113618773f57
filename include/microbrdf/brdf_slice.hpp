#pragma once
// Slices of a BRDF: f along a cut through the hemisphere of viewing directions.
//
// One convention for every slice of the project (`brdf slice`, `sun slice`, the report):
//  - the light lies in the x-z plane at azimuth 180 deg: wi = (-sin theta_i, 0, cos theta_i);
//  - in-plane:  wo(t) = (sin t, 0, cos t), t in [-90, 90] deg, signed so that the mirror
//    direction is t = +theta_i (t < 0 on the light's side);
//  - out-of-plane: wo(t) = cos t r + sin t y with r = (sin theta_i, 0, cos theta_i) the mirror
//    direction, t in [-90, 90] deg (the great circle through r perpendicular to the plane of
//    incidence).

#include <cstddef>
#include <string>
#include <vector>

#include "microbrdf/brdf.hpp"
#include "microbrdf/plot.hpp"

namespace microbrdf {

enum class SlicePlane { In, Out };
/// "in" | "out"; throws InputError naming the value otherwise.
SlicePlane parse_slice_plane(const std::string& name);
std::string to_string(SlicePlane p);

/// The light direction of every slice for the angle of incidence theta_i (rad).
Vec3 slice_light(double theta_i);
/// The viewing direction at the signed slice angle t (rad) for light at theta_i (rad).
Vec3 slice_view(double theta_i, double t, SlicePlane plane);

struct BrdfSlice {
  std::vector<double> angle_deg;  ///< signed angle t of wo (see the header comment)
  std::vector<double> value;      ///< f, 1/sr
  std::vector<Vec3> wo;
};
/// Tabulates f along an in-plane or out-of-plane cut for light at theta_i (rad); `samples` angles
/// spread evenly over [-90, 90] deg (end points nudged 1e-9 rad inside the hemisphere).
BrdfSlice tabulate_slice(const Brdf& brdf, double theta_i, double wavelength_m, SlicePlane plane,
                         std::size_t samples = 721);

/// The slice as CSV text: comment lines ("# ...": the BRDF `describe`, theta_i in deg, the
/// wavelength, the plane and its angle convention), then the header
/// angle_deg,brdf_per_sr,wo_x,wo_y,wo_z and one row per angle.
std::string slice_csv(const BrdfSlice& s, const std::string& describe, double theta_i,
                      double wavelength_m, SlicePlane plane);

/// The largest value of a slice and its angle (deg); {0, 0} for a slice that is 0 everywhere.
struct SlicePeak {
  double value = 0, angle_deg = 0;
};
SlicePeak slice_peak(const BrdfSlice& s);

/// A plot of the slice (one curve labelled `label`, cut to 70 characters) with the title and
/// axes of the convention above; `log_y` leaves out the zeros. Throws InputError when nothing is
/// left to draw.
Plot slice_plot(const BrdfSlice& s, const std::string& label, double theta_i, double wavelength_m,
                SlicePlane plane, bool log_y);

}  // namespace microbrdf
