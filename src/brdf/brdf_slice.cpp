// Slices of a BRDF and the one slice convention (include/microbrdf/brdf_slice.hpp).
#include "microbrdf/brdf_slice.hpp"

#include <cmath>
#include <cstdio>

#include "microbrdf/error.hpp"
#include "microbrdf/units.hpp"

namespace microbrdf {
namespace {
constexpr double kPi = 3.14159265358979323846;
}

SlicePlane parse_slice_plane(const std::string& name) {
  if (name == "in") return SlicePlane::In;
  if (name == "out") return SlicePlane::Out;
  throw InputError("the slice plane must be in or out (got '" + name + "')");
}

std::string to_string(SlicePlane p) { return p == SlicePlane::In ? "in" : "out"; }

Vec3 slice_light(double theta_i) { return Vec3(-std::sin(theta_i), 0, std::cos(theta_i)); }

Vec3 slice_view(double theta_i, double t, SlicePlane plane) {
  if (plane == SlicePlane::In) return Vec3(std::sin(t), 0, std::cos(t));
  const Vec3 r(std::sin(theta_i), 0, std::cos(theta_i));  // the mirror direction
  return Vec3(std::cos(t) * r + std::sin(t) * Vec3(0, 1, 0));
}

BrdfSlice tabulate_slice(const Brdf& brdf, double theta_i, double wavelength_m, SlicePlane plane,
                         std::size_t samples) {
  if (samples < 2) samples = 2;
  const Vec3 wi = slice_light(theta_i);
  BrdfSlice s;
  const double lim = kPi / 2 - 1e-9;
  for (std::size_t k = 0; k < samples; ++k) {
    const double t = -lim + 2 * lim * static_cast<double>(k) / static_cast<double>(samples - 1);
    const Vec3 wo = slice_view(theta_i, t, plane);
    s.angle_deg.push_back(t * 180 / kPi);
    s.value.push_back(brdf.eval(wi, wo, wavelength_m));
    s.wo.push_back(wo);
  }
  return s;
}

std::string slice_csv(const BrdfSlice& s, const std::string& describe, double theta_i,
                      double wavelength_m, SlicePlane plane) {
  std::string text = "# microbrdf brdf slice: " + describe + "\n";
  char line[160];
  std::snprintf(line, sizeof line,
                "# theta_i %.6g deg, wavelength %s, %s-plane; angle: ", theta_i * 180 / kPi,
                format_length(wavelength_m).c_str(), to_string(plane).c_str());
  text += line;
  text += plane == SlicePlane::In
              ? "signed theta_o in the plane of incidence (mirror at +theta_i)\n"
              : "angle from the mirror direction across the plane of incidence\n";
  text += "angle_deg,brdf_per_sr,wo_x,wo_y,wo_z\n";
  for (std::size_t i = 0; i < s.value.size(); ++i) {
    std::snprintf(line, sizeof line, "%.6f,%.9g,%.9f,%.9f,%.9f\n", s.angle_deg[i], s.value[i],
                  s.wo[i].x(), s.wo[i].y(), s.wo[i].z());
    text += line;
  }
  return text;
}

SlicePeak slice_peak(const BrdfSlice& s) {
  SlicePeak p;
  for (std::size_t i = 0; i < s.value.size(); ++i)
    if (s.value[i] > p.value) p = {s.value[i], s.angle_deg[i]};
  return p;
}

Plot slice_plot(const BrdfSlice& s, const std::string& label, double theta_i, double wavelength_m,
                SlicePlane plane, bool log_y) {
  Plot p;
  char title[200];
  std::snprintf(title, sizeof title, "BRDF, %s: θi = %g°, λ = %s",
                plane == SlicePlane::In ? "plane of incidence" : "across the plane of incidence",
                theta_i * 180 / kPi, format_length(wavelength_m).c_str());
  p.title = title;
  p.x.label = plane == SlicePlane::In ? "viewing angle θo (deg; mirror direction at +θi)"
                                      : "angle from the mirror direction across the plane (deg)";
  p.y.label = "BRDF (1/sr)";
  p.x.min = -90;
  p.x.max = 90;
  if (log_y) p.y.scale = AxisScale::Log;
  PlotSeries series;
  series.label = label.size() > 70 ? label.substr(0, 67) + "..." : label;
  for (std::size_t i = 0; i < s.value.size(); ++i) {
    if (log_y && !(s.value[i] > 0)) continue;
    series.x.push_back(s.angle_deg[i]);
    series.y.push_back(s.value[i]);
  }
  if (series.x.empty()) throw InputError("the BRDF is zero along the whole slice: nothing to plot");
  p.add(series);
  return p;
}

}  // namespace microbrdf
