#include "cli_progress.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string_view>

namespace microbrdf::cli {

Progress::Mode Progress::detect() {
  if (const char* env = std::getenv("MICROBRDF_PROGRESS")) {
    const std::string_view v(env);
    if (v == "terminal") return Mode::terminal;
    if (v == "log") return Mode::log;
    if (v == "off") return Mode::off;
  }
  return isatty(fileno(stderr)) ? Mode::terminal : Mode::log;
}

Progress::Progress(std::string command, bool quiet, double log_step, std::string label)
    : command_(std::move(command)),
      label_(label.empty() ? std::string() : label + " "),
      mode_(quiet ? Mode::off : detect()),
      log_step_(log_step > 0 ? log_step : 0.25) {}

Progress::~Progress() {
  if (open_line_) std::fputc('\n', stderr);
}

void Progress::line(const std::string& text) {
  if (mode_ == Mode::off) return;
  if (open_line_) std::fputc('\n', stderr);
  open_line_ = false;
  std::fprintf(stderr, "microbrdf %s: %s\n", command_.c_str(), text.c_str());
  std::fflush(stderr);
}

void Progress::redraw(const std::string& text) {
  // \033[K clears what a longer previous status left at the end of the line.
  std::fprintf(stderr, "\rmicrobrdf %s: %s\033[K", command_.c_str(), text.c_str());
  std::fflush(stderr);
  open_line_ = true;
}

void Progress::fraction(double f) {
  if (mode_ == Mode::off || !std::isfinite(f)) return;
  f = f < 0 ? 0 : (f > 1 ? 1 : f);
  const int pct = static_cast<int>(std::floor(f * 100 + 1e-9));
  if (pct == last_percent_) return;
  last_percent_ = pct;
  const std::string text = label_ + std::to_string(pct) + "%";
  if (mode_ == Mode::terminal) {
    redraw(text);
    if (pct == 100) {
      std::fputc('\n', stderr);
      open_line_ = false;
    }
    return;
  }
  // A log gets a line at each log_step of the work (25 %, 50 %, ... by default), 100 % included.
  const int step = static_cast<int>(std::floor(f / log_step_ + 1e-9));
  if (step < 1 || step <= last_log_step_) return;
  last_log_step_ = step;
  line(text);
}

void Progress::status(const std::string& text) {
  if (mode_ == Mode::terminal)
    redraw(text);
  else
    line(text);
}

void Progress::item(std::size_t index, std::size_t total, const std::string& what) {
  if (total <= 1) return;
  char head[48];
  std::snprintf(head, sizeof head, "[%zu/%zu] ", index + 1, total);
  line(head + what);
}

std::function<void(double)> Progress::fraction_callback() {
  return [this](double f) { fraction(f); };
}

}  // namespace microbrdf::cli
