// The Mueller matrix of the Rayleigh-Rice BRDF along a slice (include/microbrdf/rayleigh_rice.hpp),
// in the slice convention of brdf_slice.hpp.
#include <cmath>
#include <cstdio>

#include "microbrdf/brdf_slice.hpp"
#include "microbrdf/rayleigh_rice.hpp"
#include "microbrdf/units.hpp"

namespace microbrdf {

std::string mueller_slice_csv(const RayleighRiceBrdf& b, double theta_i, double wavelength_m,
                              SlicePlane plane, std::size_t samples) {
  // The same angles as tabulate_slice, so the two CSVs line up row by row.
  const BrdfSlice s = tabulate_slice(b, theta_i, wavelength_m, plane, samples);
  const Vec3 wi = slice_light(theta_i);
  std::string text = "# microbrdf brdf slice: Mueller matrix (1/sr) of " + b.describe() + "\n";
  char line[256];
  std::snprintf(line, sizeof line,
                "# theta_i %.6g deg, wavelength %s, %s-plane; Stokes (I, Q, U, V) in each beam's "
                "(s, p) basis, Q = Is - Ip; m00 = unpolarised BRDF; specular delta not included\n",
                theta_i * 180 / M_PI, format_length(wavelength_m).c_str(),
                to_string(plane).c_str());
  text += line;
  text += "angle_deg";
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) text += ",m" + std::to_string(r) + std::to_string(c);
  text += ",wo_x,wo_y,wo_z\n";
  for (std::size_t i = 0; i < s.wo.size(); ++i) {
    const auto m = b.mueller(wi, s.wo[i], wavelength_m);
    std::snprintf(line, sizeof line, "%.6f", s.angle_deg[i]);
    text += line;
    for (double v : m) {
      std::snprintf(line, sizeof line, ",%.9g", v);
      text += line;
    }
    std::snprintf(line, sizeof line, ",%.9f,%.9f,%.9f\n", s.wo[i].x(), s.wo[i].y(), s.wo[i].z());
    text += line;
  }
  return text;
}

}  // namespace microbrdf
