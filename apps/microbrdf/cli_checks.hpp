#pragma once
// Checks a command makes before any heavy work, so that a wrong flag costs a second, not the
// minutes of a render or a D_K: inputs exist, outputs have a known extension and a writable
// folder, the environment map is an EXR or Radiance file, the metal is known, numbers are in
// range. Every problem names its flag; all of them are reported at once as one InputError
// (exit code 2, a usage error). Also: CLI11 validators that name the flag, and "n/a" for values
// that do not exist.
#include <CLI/CLI.hpp>
#include <cmath>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

namespace microbrdf::cli {

class Preflight {
 public:
  /// An input file (or folder, for scan sets) that must exist and be readable.
  Preflight& input(std::string_view flag, const std::string& path);
  /// An output file: its extension must be one of `extensions` (lower case, with the dot; case
  /// is ignored), it must not be a folder, and its folder must exist and be writable.
  Preflight& output(std::string_view flag, const std::string& path,
                    std::initializer_list<std::string_view> extensions);
  /// A height-map output: an extension the surface writer writes (io.hpp: format_can_write),
  /// not a folder, in an existing writable folder.
  Preflight& height_map_output(std::string_view flag, const std::string& path);
  /// An output folder: it is created later, so its parent must exist and be writable (or the
  /// folder itself must exist and be writable).
  Preflight& output_dir(std::string_view flag, const std::string& path);
  /// An environment map: readable, with the signature of an OpenEXR or a Radiance .hdr file.
  Preflight& envmap(std::string_view flag, const std::string& path);
  /// A built-in metal name (`microbrdf::metal`).
  Preflight& metal(std::string_view flag, const std::string& name);
  /// value > 0 (and finite).
  Preflight& positive(std::string_view flag, double value);
  /// lo <= value <= hi.
  Preflight& in_range(std::string_view flag, double value, double lo, double hi);
  /// Any other condition; `problem` is said after the flag when `ok` is false.
  Preflight& require(bool ok, std::string_view flag, const std::string& problem);

  const std::vector<std::string>& problems() const { return problems_; }
  /// Throws InputError listing every problem ("--flag: problem; --other: problem") if any.
  void done() const;

 private:
  void add(std::string_view flag, const std::string& problem);
  void writable_parent(std::string_view flag, const std::string& path);  // the folder of `path`
  std::vector<std::string> problems_;
};

/// CLI11 validators; CLI11 prefixes the message with the flag ("--alpha: must be > 0 (got
/// -0.1)"), and main() turns every parse error into exit code 2.
CLI::Validator positive_number(double hi = HUGE_VAL);  // 0 < v <= hi
CLI::Validator number_in(double lo, double hi);
/// A whole number in [lo, hi] (counts with a budget: rays, samples, pixels). The message says
/// why the upper limit exists when `why` is given ("--rays: must be in [1, 1e+10] ...: why").
CLI::Validator count_in(double lo, double hi, std::string why = {});

/// The most Monte Carlo samples (rays, exits, profile samples) one run takes: 1e10, about three
/// hours at the tracers' ~1e6 per second and core; beyond it a count is a typo, not a plan.
inline constexpr double kMaxSamples = 1e10;
inline constexpr const char* kWhySamples =
    "beyond 1e10 samples a run takes hours (~1e6 per second and core)";

/// A length with a unit ("110nm", "1.5 um") in [lo, hi] metres; the message names the flag and
/// prints the range with SI prefixes ("--spacing: must lie in 1 pm .. 1 m (got 1e300m)"). Any of
/// `words` (e.g. "auto") is accepted as it is.
CLI::Validator length_in(double lo, double hi, std::initializer_list<const char*> words = {});
/// One length or a pair ("110nm" or "110x130nm"), each in [lo, hi] metres.
CLI::Validator length_or_pair_in(double lo, double hi);
/// A pair of lengths ("70x53um"), each in [lo, hi] metres.
CLI::Validator length_pair_in(double lo, double hi);
/// The lengths the tool accepts at all: 1 pm (below any instrument's resolution) .. 1 m (above
/// any scan's size); the same range the readers apply to a file's sample spacing.
inline constexpr double kMinLength = 1e-12, kMaxLength = 1.0;
/// A height (rms height, depth, amplitude): 0 .. 1 m.
CLI::Validator height();
/// A lateral distance (correlation length, period, filter sigma, texel): 1 pm .. 1 m.
CLI::Validator distance();
/// A direction in the surface plane (an azimuth): -360 .. 360 deg.
CLI::Validator direction();
/// A polar angle from the normal: 0 .. 90 deg.
CLI::Validator polar_angle();
/// The optical wavelengths the tool models: 100 nm .. 20 um (the optical constants' range).
CLI::Validator wavelength();
/// An angle ("30deg", "0.5rad", a bare number is degrees) in [lo, hi] radians, printed in
/// degrees. With `list`, a comma-separated list of such angles.
CLI::Validator angle_in(double lo, double hi, bool list = false);

/// Every integer option of `app` and its subcommands (CLI11 type INT or UINT; all are counts or
/// sizes) takes plain decimal digits only: CLI11 2.1 reads "-1" for an unsigned count as
/// 2^64 - 1, saturates a value beyond 64 bits silently and reads "010" as octal. Call after
/// every option is added.
void guard_integer_options(CLI::App& app);

/// printf-style formatting of a number, or "n/a" when it does not exist (NaN or infinite).
std::string number_or_na(double v, const char* format = "%.4g");

}  // namespace microbrdf::cli
