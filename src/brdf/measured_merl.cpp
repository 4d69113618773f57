// MERL 100 `.binary` tables: reader, writer, tabulation and the table as a Brdf
// (include/microbrdf/measured.hpp; docs/measured.md).
#include <cmath>
#include <cstring>

#include "core/byte_reader.hpp"
#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/io.hpp"
#include "microbrdf/measured.hpp"

namespace microbrdf {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kScale[3] = {1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0};
constexpr std::size_t kFileBytes = 12 + 3 * MerlTable::kBins * 8;

Vec3 rotate_z(const Vec3& v, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y(), v.z()};
}
Vec3 rotate_y(const Vec3& v, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {c * v.x() + s * v.z(), v.y(), -s * v.x() + c * v.z()};
}

}  // namespace

std::array<double, 3> merl_channel_wavelengths() { return {630e-9, 532e-9, 465e-9}; }

double merl_theta_half(int i) {
  const double u = (i + 0.5) / MerlTable::kThetaH;
  return u * u * kPi / 2;
}
double merl_theta_diff(int j) { return (j + 0.5) / MerlTable::kThetaD * kPi / 2; }
double merl_phi_diff(int k) { return (k + 0.5) / MerlTable::kPhiD * kPi; }

void merl_directions(double theta_h, double theta_d, double phi_d, Vec3& wi, Vec3& wo) {
  const Vec3 d(std::sin(theta_d) * std::cos(phi_d), std::sin(theta_d) * std::sin(phi_d),
               std::cos(theta_d));
  const Vec3 h(std::sin(theta_h), 0, std::cos(theta_h));
  wi = rotate_y(d, theta_h);
  wo = 2 * wi.dot(h) * h - wi;
}

std::array<double, 3> merl_coordinates(const Vec3& wi, const Vec3& wo) {
  const Vec3 h = (wi + wo).normalized();
  const double theta_h = std::acos(std::clamp(h.z(), -1.0, 1.0));
  const double phi_h = std::atan2(h.y(), h.x());
  const Vec3 d = rotate_y(rotate_z(wi, -phi_h), -theta_h);
  const double theta_d = std::acos(std::clamp(d.z(), -1.0, 1.0));
  double phi_d = std::atan2(d.y(), d.x());
  if (phi_d < 0) phi_d += kPi;  // reciprocity: phi_d and phi_d + pi are the same bin
  if (phi_d >= kPi) phi_d -= kPi;
  return {theta_h, theta_d, phi_d};
}

MerlTable parse_merl(std::span<const std::uint8_t> bytes, const std::string& name) {
  detail::ByteReader r(bytes, name);
  const std::int32_t n1 = r.le<std::int32_t>(0, "dimension 1");
  const std::int32_t n2 = r.le<std::int32_t>(4, "dimension 2");
  const std::int32_t n3 = r.le<std::int32_t>(8, "dimension 3");
  if (n1 != MerlTable::kThetaH || n2 != MerlTable::kThetaD || n3 != MerlTable::kPhiD)
    r.fail("not a MERL BRDF: dimensions " + std::to_string(n1) + " x " + std::to_string(n2) +
           " x " + std::to_string(n3) + " (90 x 90 x 180 expected)");
  if (bytes.size() != kFileBytes)
    r.fail("truncated or corrupt MERL file: " + std::to_string(bytes.size()) + " bytes (" +
           std::to_string(kFileBytes) + " expected)");
  MerlTable t;
  for (std::size_t i = 0; i < 3 * MerlTable::kBins; ++i) {
    double v;
    std::memcpy(&v, bytes.data() + 12 + 8 * i, 8);
    const int c = static_cast<int>(i / MerlTable::kBins);
    if (!std::isfinite(v)) r.fail("non-finite value in bin " + std::to_string(i));
    t.rgb[i] = v < 0 ? std::numeric_limits<double>::quiet_NaN() : v * kScale[c];
  }
  return t;
}

MerlTable read_merl(const std::string& path) {
  return parse_merl(read_file_bytes(path, kFileBytes + 1), path);
}

std::vector<std::uint8_t> encode_merl(const MerlTable& t) {
  std::vector<std::uint8_t> out(kFileBytes);
  const std::int32_t dims[3] = {MerlTable::kThetaH, MerlTable::kThetaD, MerlTable::kPhiD};
  std::memcpy(out.data(), dims, 12);
  for (std::size_t i = 0; i < 3 * MerlTable::kBins; ++i) {
    const int c = static_cast<int>(i / MerlTable::kBins);
    const double v = std::isnan(t.rgb[i]) ? -1.0 : t.rgb[i] / kScale[c];
    std::memcpy(out.data() + 12 + 8 * i, &v, 8);
  }
  return out;
}

void write_merl(const MerlTable& t, const std::string& path) {
  write_file_atomic(path, encode_merl(t));
}

MerlTable tabulate_merl(const Brdf& brdf) {
  MerlTable t;
  const auto wl = merl_channel_wavelengths();
#pragma omp parallel for schedule(dynamic)
  for (int i = 0; i < MerlTable::kThetaH; ++i)
    for (int j = 0; j < MerlTable::kThetaD; ++j)
      for (int k = 0; k < MerlTable::kPhiD; ++k) {
        Vec3 wi, wo;
        merl_directions(merl_theta_half(i), merl_theta_diff(j), merl_phi_diff(k), wi, wo);
        const std::size_t b = MerlTable::index(i, j, k);
        for (int c = 0; c < 3; ++c)
          t.rgb[c * MerlTable::kBins + b] = (wi.z() > 0 && wo.z() > 0)
                                                ? brdf.eval(wi, wo, wl[c])
                                                : std::numeric_limits<double>::quiet_NaN();
      }
  return t;
}

MerlBrdf::MerlBrdf(MerlTable t, std::string source)
    : t_(std::move(t)), source_(std::move(source)) {}

double MerlBrdf::eval_channel(const Vec3& wi, const Vec3& wo, int channel) const {
  if (wi.z() <= 0 || wo.z() <= 0) return 0;
  const auto c = merl_coordinates(wi, wo);
  // Continuous bin indices with bin centres at integers.
  const double x[3] = {std::sqrt(c[0] / (kPi / 2)) * MerlTable::kThetaH - 0.5,
                       c[1] / (kPi / 2) * MerlTable::kThetaD - 0.5,
                       c[2] / kPi * MerlTable::kPhiD - 0.5};
  const int n[3] = {MerlTable::kThetaH, MerlTable::kThetaD, MerlTable::kPhiD};
  int i0[3], i1[3];
  double w1[3];
  for (int a = 0; a < 3; ++a) {
    double v = x[a];
    if (a < 2) v = std::clamp(v, 0.0, double(n[a] - 1));  // theta: constant beyond the centres
    const double f = std::floor(v);
    w1[a] = v - f;
    i0[a] = static_cast<int>(f);
    i1[a] = i0[a] + 1;
    if (a == 2) {  // phi_d: periodic with period 180 deg
      i0[a] = (i0[a] % n[a] + n[a]) % n[a];
      i1[a] = (i1[a] % n[a] + n[a]) % n[a];
    } else {
      i1[a] = std::min(i1[a], n[a] - 1);
    }
  }
  const double* data = t_.rgb.data() + std::size_t(channel) * MerlTable::kBins;
  double sum = 0, wsum = 0;
  for (int corner = 0; corner < 8; ++corner) {
    double w = 1;
    int idx[3];
    for (int a = 0; a < 3; ++a) {
      const bool hi = (corner >> a) & 1;
      idx[a] = hi ? i1[a] : i0[a];
      w *= hi ? w1[a] : 1 - w1[a];
    }
    if (w <= 0) continue;
    const double v = data[MerlTable::index(idx[0], idx[1], idx[2])];
    if (std::isnan(v)) continue;
    sum += w * v;
    wsum += w;
  }
  return wsum > 1e-12 ? sum / wsum : std::numeric_limits<double>::quiet_NaN();
}

double MerlBrdf::eval(const Vec3& wi, const Vec3& wo, double wavelength_m) const {
  if (wi.z() <= 0 || wo.z() <= 0) return 0;
  const auto wl = merl_channel_wavelengths();  // descending: R, G, B
  if (wavelength_m >= wl[0]) return eval_channel(wi, wo, 0);
  if (wavelength_m <= wl[2]) return eval_channel(wi, wo, 2);
  const int hi = wavelength_m >= wl[1] ? 0 : 1;  // channel with the longer wavelength
  const double t = (wavelength_m - wl[hi + 1]) / (wl[hi] - wl[hi + 1]);
  return t * eval_channel(wi, wo, hi) + (1 - t) * eval_channel(wi, wo, hi + 1);
}

std::optional<BrdfSample> MerlBrdf::sample(const Vec3& wi, double u1, double u2,
                                           double wavelength_m) const {
  if (wi.z() <= 0) return std::nullopt;
  const double r = std::sqrt(u1), phi = 2 * kPi * u2;
  const Vec3 wo(r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0, 1 - u1)));
  if (wo.z() <= 0) return std::nullopt;
  const double p = wo.z() / kPi;
  const double f = eval(wi, wo, wavelength_m);
  if (!std::isfinite(f)) return std::nullopt;
  return BrdfSample{wo, f * wo.z() / p, p};
}

double MerlBrdf::pdf(const Vec3& wi, const Vec3& wo) const {
  return (wi.z() > 0 && wo.z() > 0) ? wo.z() / kPi : 0.0;
}

std::string MerlBrdf::describe() const {
  return "MERL measured BRDF" + (source_.empty() ? std::string() : " (" + source_ + ")");
}

}  // namespace microbrdf
