#pragma once
// The one progress reporter of the command line. On a terminal it redraws one status line in
// place ("\r"); when stderr is a file or a pipe it never writes a carriage return: it writes a
// plain line at coarse steps (every `log_step` of the work, and at 100 %), so logs stay
// readable. MICROBRDF_PROGRESS=terminal|log|off overrides the detection (tests, CI logs).
#include <cstddef>
#include <functional>
#include <string>

namespace microbrdf::cli {

class Progress {
 public:
  enum class Mode { terminal, log, off };

  /// `command` prefixes every line ("microbrdf render: ..."); `quiet` turns everything off;
  /// `label` precedes the percentage ("kirchhoff D_K 40%").
  explicit Progress(std::string command, bool quiet = false, double log_step = 0.25,
                    std::string label = "");
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  /// Fraction of the work done, in [0, 1] ("42%"); repeated values are dropped.
  void fraction(double f);
  /// A free-form status ("1200 directions, Q = 0.01"): redrawn on a terminal, a line in a log.
  void status(const std::string& text);
  /// "[3/10] scan.x3p" before item `index` (0-based) of `total`; nothing when total <= 1.
  void item(std::size_t index, std::size_t total, const std::string& what);
  /// A callback for library options that report a fraction (RenderOptions::progress, ...).
  std::function<void(double)> fraction_callback();

  Mode mode() const { return mode_; }
  /// The mode for stderr: MICROBRDF_PROGRESS if set, else terminal when stderr is a TTY.
  static Mode detect();

 private:
  void line(const std::string& text);  // a finished line (ends a redrawn one first)
  void redraw(const std::string& text);
  std::string command_;
  std::string label_;
  Mode mode_;
  double log_step_;
  int last_percent_ = -1;
  int last_log_step_ = -1;
  bool open_line_ = false;  // a redrawn status line without its newline yet
};

}  // namespace microbrdf::cli
