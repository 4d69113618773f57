#pragma once
// Measured BRDFs: MERL 100 `.binary` tables and gonioreflectometer point sets (CSV), their
// readers and writers, and the MERL table as a Brdf. docs/measured.md describes the formats and
// conventions; every reader checks sizes against the bytes it holds before allocating.
//
// Directions follow brdf.hpp: wi (light) and wo (viewer) point away from the surface, n = +z.

#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "microbrdf/brdf.hpp"

namespace microbrdf {

// ---------------------------------------------------------------------------------------------
// MERL 100 (Matusik et al. 2003): int32 dims {90, 90, 180} over (theta_half, theta_diff,
// phi_diff), then three blocks (R, G, B) of 90*90*180 float64 values, little-endian, index
// ((i_th * 90) + i_td) * 180 + i_pd; stored value * scale = BRDF in 1/sr with scales
// 1/1500, 1.15/1500, 1.66/1500; negative values mark bins without data.
//  - theta_half bin i covers sqrt(theta_h / 90 deg) * 90 in [i, i+1) (square-root spacing);
//    theta_diff bin j covers theta_d / 90 deg * 90 in [j, j+1); phi_diff bin k covers
//    phi_d / 180 deg * 180 in [k, k+1), phi_d taken modulo 180 deg (reciprocity).
//  - Rusinkiewicz coordinates: h = (wi + wo)/|wi + wo|; d = wi expressed in the frame of h
//    (rotate by -phi_h about n, then by -theta_h about the binormal).
// MerlBrdf interpolates trilinearly between bin centres (index + 1/2); invalid bins drop out of
// the weights (all eight invalid: NaN, "unmeasured").

struct MerlTable {
  static constexpr int kThetaH = 90, kThetaD = 90, kPhiD = 180;
  static constexpr std::size_t kBins = std::size_t(kThetaH) * kThetaD * kPhiD;
  /// channel c (0 R, 1 G, 2 B) at bin b is rgb[c * kBins + b]: BRDF in 1/sr, NaN = no data.
  std::vector<double> rgb = std::vector<double>(3 * kBins, 0.0);
  static std::size_t index(int i_th, int i_td, int i_pd) {
    return (std::size_t(i_th) * kThetaD + std::size_t(i_td)) * kPhiD + std::size_t(i_pd);
  }
};

/// Wavelengths (m) the three channels stand for: R 630 nm, G 532 nm, B 465 nm. A wavelength in
/// between interpolates linearly between the two neighbouring channels (clamped at the ends).
std::array<double, 3> merl_channel_wavelengths();

/// Bin centre (rad) of each coordinate: theta_h = ((i + 1/2)/90)^2 90 deg,
/// theta_d = (j + 1/2) deg, phi_d = (k + 1/2) deg.
double merl_theta_half(int i);
double merl_theta_diff(int j);
double merl_phi_diff(int k);
/// The (wi, wo) of Rusinkiewicz coordinates (rad).
void merl_directions(double theta_h, double theta_d, double phi_d, Vec3& wi, Vec3& wo);
/// Rusinkiewicz coordinates of (wi, wo): theta_h, theta_d, phi_d (phi_d in [0, pi)).
std::array<double, 3> merl_coordinates(const Vec3& wi, const Vec3& wo);

/// Parses a MERL file held in memory: exactly 12 + 3 * 90*90*180 * 8 bytes with dims
/// {90, 90, 180}. Throws FileError(name, ...).
MerlTable parse_merl(std::span<const std::uint8_t> bytes, const std::string& name);
MerlTable read_merl(const std::string& path);
/// The file's bytes (NaN is written as -1, the MERL "no data" marker).
std::vector<std::uint8_t> encode_merl(const MerlTable& t);
void write_merl(const MerlTable& t, const std::string& path);
/// Tabulates a BRDF at the bin centres, channel c evaluated at merl_channel_wavelengths()[c].
MerlTable tabulate_merl(const Brdf& brdf);

/// A MERL table as a Brdf (isotropic by construction). Sampling is cosine-weighted.
class MerlBrdf final : public Brdf {
 public:
  explicit MerlBrdf(MerlTable t, std::string source = "");
  double eval(const Vec3& wi, const Vec3& wo, double wavelength_m) const override;
  std::optional<BrdfSample> sample(const Vec3& wi, double u1, double u2,
                                   double wavelength_m) const override;
  double pdf(const Vec3& wi, const Vec3& wo) const override;
  std::string describe() const override;
  /// One channel, trilinear between bin centres; NaN where no neighbouring bin has data.
  double eval_channel(const Vec3& wi, const Vec3& wo, int channel) const;
  const MerlTable& table() const { return t_; }

 private:
  MerlTable t_;
  std::string source_;
};

// ---------------------------------------------------------------------------------------------
// Gonioreflectometer point sets: CSV with a header naming at least
//   theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,wavelength_nm,brdf_per_sr
// in any order; an optional brdf_sigma_per_sr (one standard deviation); other columns are
// ignored; '#' lines and blank lines are skipped. Angles in degrees (theta in [0, 90],
// phi any), wavelength in nm, BRDF in 1/sr. wi = (sin ti cos pi, sin ti sin pi, cos ti).

struct GonioPoint {
  double theta_i = 0, phi_i = 0, theta_o = 0, phi_o = 0;  ///< rad
  double wavelength_m = 0;
  double brdf = 0;                                          ///< 1/sr
  double sigma = std::numeric_limits<double>::quiet_NaN();  ///< 1/sr; NaN when not given
  Vec3 wi() const;
  Vec3 wo() const;
};

struct GonioData {
  std::vector<GonioPoint> points;
  bool has_sigma = false;
};

/// Parses CSV text (a leading UTF-8 byte-order mark is skipped). Throws FileError(name,
/// "line N: ...") for a missing column, a malformed number, an angle out of range, a
/// non-positive wavelength or a negative BRDF value.
GonioData parse_gonio_csv(std::string_view text, const std::string& name);
GonioData read_gonio_csv(const std::string& path);
std::string encode_gonio_csv(const GonioData& d);
void write_gonio_csv(const GonioData& d, const std::string& path);

}  // namespace microbrdf
