#pragma once
// A virtual in-plane gonioreflectometer on a micro-scene: rho estimated directly in cones around
// directions of the plane of incidence (cap_brdf), with the He 1991 geometric limit and the
// Beckmann-Smith microfacet BRDF averaged over the same cones as references (Westin 1992 Fig. 6,
// docs/theory.md §6.7). `microbrdf simulate --in-plane` and the tests run this one function.
//
// Convention (the slice convention of brdf_slice.hpp, turned by phi_i about n): the light lies at
// azimuth phi_i + 180 deg, wi = (-cos phi_i sin theta_i, -sin phi_i sin theta_i, cos theta_i);
// the exit directions are wo(t) = (cos phi_i sin t, sin phi_i sin t, cos t), t signed so that the
// mirror direction is t = +theta_i.

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "microbrdf/microscene.hpp"
#include "microbrdf/sh_brdf.hpp"
#include "microbrdf/simulate.hpp"
#include "microbrdf/vec3.hpp"

namespace microbrdf {

/// Sample counts of cone_average (and so of every cone-averaged reference of the goniometer).
constexpr int kConeRings = 6, kConeAzimuths = 16;

/// The cosine-weighted mean of f over the cone of half-angle `half` (rad) around the unit
/// direction c: kConeRings rings at r = (i + 1/2) half / kConeRings, kConeAzimuths directions
/// each (from t1 = normalise(axis x c) round to t2 = c x t1), weights sin(r) w_z. `axis` is a
/// direction in the surface perpendicular to the plane of incidence. What a detector of that
/// aperture measures of a BRDF.
double cone_average(const std::function<double(const Vec3&)>& f, const Vec3& c, double half,
                    const Vec3& axis);

struct GoniometerOptions {
  std::vector<double> theta_i_rad;      ///< angles of incidence, each in [0, pi/2)
  double cone_half_angle_rad = 0.0698;  ///< exit cones (4 deg), in (0, 20 deg)
  double phi_i_rad = 0;                 ///< azimuth of the plane of incidence
  /// Exit angles t (deg): from t_min to t_max in steps, leaving out those whose cone reaches
  /// the horizon (|t| + half >= 90 deg).
  double theta_r_min_deg = -85, theta_r_max_deg = 85, theta_r_step_deg = 2.5;
  std::uint64_t rays = 200000;  ///< per angle of incidence
  TraceOptions trace;
  std::uint64_t seed = 1;       ///< the k-th angle of incidence uses seed + k
  bool isotropic = false;       ///< turn the plane of incidence at random (isotropic scenes)
  bool single_scatter = false;  ///< also the one-bounce part (trace.max_depth = 1)
  /// Reference surface (both > 0: He 1991 and Beckmann-Smith with alpha = 2 sigma / tau, with the
  /// Fresnel term of the first height field's mirror material, else F = 1), metres.
  double he_sigma_m = 0, he_tau_m = 0;
  std::shared_ptr<const ShBrdf> sh;  ///< overlay (evaluated at the cone centres); optional
};

struct GoniometerCurve {
  double theta_i_rad = 0;
  std::vector<double> theta_r_deg;
  std::vector<double> simulated, simulated_single;  ///< rho, 1/sr (single: when asked)
  std::vector<double> he1991, beckmann_smith, sh;   ///< references (empty when not asked)
  double albedo = 0;                                ///< energy out / rays
  double energy_below = 0;                          ///< energy through the bottom / rays
};

/// Runs the goniometer: one curve per angle of incidence, in order; `done` is called after each.
/// Throws InputError for options outside their ranges.
std::vector<GoniometerCurve> in_plane_goniometer(
    const MicroScene& scene, const GoniometerOptions& options,
    const std::function<void(const GoniometerCurve&)>& done = {});

}  // namespace microbrdf
