#pragma once
// Tables generated at build time by src/models/generate_tables.cmake (internal header).
//  - CIE 1931 2-degree colour matching functions and CIE D65 relative SPD from Debian's
//    colord-data package, on their 5 nm grids (D65 scaled to 1 at 560 nm).
//  - Optical constants n, k of metals from data/optical/*.csv, wavelengths in nm.
#include <cstddef>

namespace microbrdf::detail {

extern const double kCmfStartNm, kCmfEndNm;
extern const std::size_t kCmfBands;
extern const double kCmfX[], kCmfY[], kCmfZ[];

extern const double kD65StartNm, kD65EndNm;
extern const std::size_t kD65Bands;
extern const double kD65[];

struct OpticalTable {
  const char* name;  ///< file stem, e.g. "Au_JohnsonChristy1972"
  const double* wavelength_nm;
  const double* n;
  const double* k;
  std::size_t size;
};
extern const OpticalTable kOpticalTables[];
extern const std::size_t kOpticalTableCount;

}  // namespace microbrdf::detail
