#pragma once
// `microbrdf ndf`: the flags (shared by cmd_ndf.cpp, which registers them and computes D_K, and
// ndf_geometric.cpp, the naive and filtered NDFs with --filter-sigma auto).
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli_common.hpp"
#include "kirchhoff_flags.hpp"
#include "microbrdf/filter_sigma_auto.hpp"
#include "microbrdf/kirchhoff.hpp"
#include "microbrdf/ndf_scanset.hpp"
#include "microbrdf/tabulated_ndf.hpp"

namespace microbrdf::cli {

struct NdfArgs {
  std::vector<std::string> inputs;
  ReadFlags read;
  std::string method = "filtered";
  std::string filter_sigma = "1um";
  std::size_t resolution = 1025;
  double min_support = 0.5;
  std::string output, preview, instrument_fwhm = "0", instrument;
  bool zoom = false;
  bool json = false;
  std::string wavelength = "555nm";  // Kirchhoff options from here on
  KirchhoffFlags dk;
  bool direct = false;
  std::size_t sweep_resolution = FilterSigmaAutoOptions{}.resolution;  // --filter-sigma auto
};

/// The --json object common to every method.
nlohmann::json ndf_json(const TabulatedNdf& ndf, const NdfArgs& a);
/// The instrument signature (every method), the table (-o) and, when asked, its preview.
void write_outputs(TabulatedNdf& ndf, const NdfArgs& a);
/// Every table of a stack over lambda_q (instrument applied to each) into -o; the preview of
/// layers[primary].
void write_outputs(std::vector<TabulatedNdf>& layers, std::size_t primary, const NdfArgs& a);
/// Reading and levelling of the scan set (distributed over MPI ranks when run under mpirun).
ScanSetOptions scan_set_options(const NdfArgs& a, std::size_t scans);
/// --method naive | filtered (with --filter-sigma auto).
void run_geometric(const NdfArgs& a);

}  // namespace microbrdf::cli
