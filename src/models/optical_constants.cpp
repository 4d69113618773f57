// Optical constants of materials (include/microbrdf/fresnel.hpp). The built-in metals are
// generated at build time from data/optical/*.csv (see data/optical/README.md).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "microbrdf/error.hpp"
#include "microbrdf/file_read.hpp"
#include "microbrdf/fresnel.hpp"
#include "models/tables.hpp"

namespace microbrdf {
namespace {

struct Alias {
  const char* name;
  const char* stem;
  const char* source;
};
constexpr Alias kAliases[] = {
    {"Au", "Au_JohnsonChristy1972", "Johnson & Christy 1972, Phys. Rev. B 6, 4370"},
    {"Ag", "Ag_JohnsonChristy1972", "Johnson & Christy 1972, Phys. Rev. B 6, 4370"},
    {"Cu", "Cu_JohnsonChristy1972", "Johnson & Christy 1972, Phys. Rev. B 6, 4370"},
    {"Al", "Al_Rakic1995", "Rakic 1995, Appl. Opt. 34, 4755"},
    {"Fe", "Fe_JohnsonChristy1974", "Johnson & Christy 1974, Phys. Rev. B 9, 5056"},
    {"Cr", "Cr_JohnsonChristy1974", "Johnson & Christy 1974, Phys. Rev. B 9, 5056"},
    {"Ni", "Ni_JohnsonChristy1974", "Johnson & Christy 1974, Phys. Rev. B 9, 5056"},
    {"Ti", "Ti_JohnsonChristy1974", "Johnson & Christy 1974, Phys. Rev. B 9, 5056"},
    {"Pt", "Pt_RakicLD1998", "Rakic et al. 1998 Lorentz-Drude model, Appl. Opt. 37, 5271"},
    {"Pt-Tselin", "Pt_Tselin2024", "Tselin et al. 2024, Phys. Rev. B 110, 195130"},
    {"SS-austenitic", "StainlessSteelAustenitic_Karlsson1982",
     "Karlsson & Ribbing 1982, J. Appl. Phys. 53, 6340"},
    {"SS-ferritic", "StainlessSteelFerritic_Karlsson1982",
     "Karlsson & Ribbing 1982, J. Appl. Phys. 53, 6340"},
};

std::string lower(std::string_view s) {
  std::string r(s);
  for (auto& c : r) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return r;
}

OpticalConstants from_table(const detail::OpticalTable& t, const std::string& name,
                            const std::string& source) {
  std::vector<double> nm(t.wavelength_nm, t.wavelength_nm + t.size);
  OpticalConstants c;
  c.name = name;
  c.source = source;
  c.n = Spectrum::from_nm(nm, std::vector<double>(t.n, t.n + t.size));
  c.k = Spectrum::from_nm(nm, std::vector<double>(t.k, t.k + t.size));
  return c;
}

}  // namespace

Spectrum OpticalConstants::normal_reflectance_spectrum() const {
  std::vector<double> lambda = colour_wavelengths(), r(lambda.size());
  for (std::size_t i = 0; i < lambda.size(); ++i)
    r[i] = normal_reflectance(n(lambda[i]), k(lambda[i]));
  return Spectrum(std::move(lambda), std::move(r));
}

std::vector<std::string> metal_names() {
  std::vector<std::string> v;
  for (const auto& a : kAliases) v.emplace_back(a.name);
  return v;
}

OpticalConstants metal(std::string_view name) {
  const std::string key = lower(name);
  for (const auto& a : kAliases) {
    if (key != lower(a.name) && key != lower(a.stem)) continue;
    for (std::size_t i = 0; i < detail::kOpticalTableCount; ++i)
      if (std::string_view(detail::kOpticalTables[i].name) == a.stem)
        return from_table(detail::kOpticalTables[i], a.name, a.source);
  }
  for (std::size_t i = 0; i < detail::kOpticalTableCount; ++i)  // tables added without an alias
    if (key == lower(detail::kOpticalTables[i].name))
      return from_table(detail::kOpticalTables[i], detail::kOpticalTables[i].name, "data/optical");
  std::string names;
  for (const auto& n : metal_names()) names += (names.empty() ? "" : " ") + n;
  throw InputError("unknown metal '" + std::string(name) + "' (known: " + names + ")");
}

OpticalConstants constant_index(double n, double k) {
  if (!(n > 0) || !(k >= 0) || !std::isfinite(n) || !std::isfinite(k))
    throw InputError("optical constants need n > 0 and k >= 0");
  OpticalConstants c;
  c.name = "custom";
  std::ostringstream s;
  s << "n = " << n << ", k = " << k;
  c.source = s.str();
  c.n = Spectrum::constant(n);
  c.k = Spectrum::constant(k);
  return c;
}

OpticalConstants read_optical_constants_csv(const std::string& path) {
  require_regular_file(path);  // a FIFO or device would block or never end
  std::ifstream in(path);
  if (!in) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw FileError::missing(path);
    throw FileError(path, "cannot open");
  }
  std::string line;
  double scale = 0;
  std::vector<double> wl, n, k;
  std::size_t lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    if (scale == 0) {
      std::string h = lower(line);
      h.erase(std::remove_if(h.begin(), h.end(), [](char c) { return c == ' ' || c == '\t'; }),
              h.end());
      if (h == "wavelength_nm,n,k")
        scale = 1e-9;
      else if (h == "wavelength_um,n,k")
        scale = 1e-6;
      else
        throw FileError(
            path, "line " + std::to_string(lineno) + ": expected the header 'wavelength_nm,n,k'");
      continue;
    }
    std::istringstream ls(line);
    double v[3];
    char comma;
    if (!(ls >> v[0] >> comma >> v[1] >> comma >> v[2]) || !std::isfinite(v[0]) ||
        !std::isfinite(v[1]) || !std::isfinite(v[2]))
      throw FileError(
          path, "line " + std::to_string(lineno) + ": expected three numbers 'wavelength,n,k'");
    if (v[0] <= 0 || v[1] <= 0 || v[2] < 0)
      throw FileError(path,
                      "line " + std::to_string(lineno) + ": need wavelength > 0, n > 0, k >= 0");
    if (!wl.empty() && v[0] * scale <= wl.back())
      throw FileError(path, "line " + std::to_string(lineno) + ": wavelengths must increase");
    wl.push_back(v[0] * scale);
    n.push_back(v[1]);
    k.push_back(v[2]);
  }
  if (wl.empty()) throw FileError(path, "no data rows");
  OpticalConstants c;
  c.name = path;
  c.source = path;
  c.n = Spectrum(wl, std::move(n));
  c.k = Spectrum(std::move(wl), std::move(k));
  return c;
}

OpticalConstants from_normal_reflectance(const Spectrum& r0, double eta) {
  if (r0.empty()) throw InputError("empty reflectance spectrum");
  std::vector<double> kv(r0.size());
  for (std::size_t i = 0; i < kv.size(); ++i)
    kv[i] = kappa_from_normal_reflectance(r0.values()[i], eta);
  OpticalConstants c;
  c.name = "from R0";
  c.source =
      "Sun 2002 section 5.2: eta = " + std::to_string(eta) + ", kappa from the normal reflectance";
  c.n = Spectrum(r0.wavelengths(), std::vector<double>(r0.size(), eta));
  c.k = Spectrum(r0.wavelengths(), std::move(kv));
  return c;
}

OpticalConstants from_srgb(double r, double g, double b) {
  Eigen::Vector3d lin(srgb_decode(r), srgb_decode(g), srgb_decode(b));
  for (int i = 0; i < 3; ++i)
    if (!(lin[i] > 0 && lin[i] < 0.999))
      throw InputError(
          "sRGB colour components must lie strictly inside (0, 1) to be a metal's reflectance");
  auto c = from_normal_reflectance(smooth_reflectance_from_linear_srgb(lin), 1.0);
  c.name = "from sRGB";
  c.source =
      "smooth reflectance spectrum fitted to the sRGB colour, eta = 1, kappa from R0 (Sun 2002 "
      "sec. 5.2)";
  return c;
}

}  // namespace microbrdf
