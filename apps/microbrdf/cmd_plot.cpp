// `microbrdf plot DATA.csv --x COL --y COL,... -o plot.png`: line plots of CSV columns, so
// figures in the docs (and a user's own comparisons) are drawn by the tool itself.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>

#include "cli_common.hpp"
#include "commands.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/plot.hpp"

namespace microbrdf::cli {
namespace {

struct PlotArgs {
  std::string input, output, x, title, xlabel, ylabel;
  std::vector<std::string> y, labels, styles;
  bool logx = false, logy = false;
};

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) {
    auto b = cell.find_first_not_of(" \t\r"), e = cell.find_last_not_of(" \t\r");
    out.push_back(b == std::string::npos ? "" : cell.substr(b, e - b + 1));
  }
  return out;
}

PlotStyle style_of(const std::string& s) {
  if (s == "line") return PlotStyle::Line;
  if (s == "dashed") return PlotStyle::Dashed;
  if (s == "dotted") return PlotStyle::Dotted;
  if (s == "markers") return PlotStyle::Markers;
  if (s == "linemarkers") return PlotStyle::LineMarkers;
  throw InputError("unknown style '" + s + "' (line, dashed, dotted, markers, linemarkers)");
}

void run(const PlotArgs& a) {
  std::ifstream in(a.input);
  if (!in) throw FileError(a.input, "cannot open");
  std::string line;
  std::vector<std::string> header;
  std::vector<std::vector<double>> cols;
  std::size_t lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    if (line.empty() || line[0] == '#') continue;
    auto cells = split(line);
    if (header.empty()) {
      header = cells;
      cols.resize(header.size());
      continue;
    }
    if (cells.size() != header.size())
      throw FileError(a.input, "line " + std::to_string(lineno) + " has " +
                                   std::to_string(cells.size()) + " columns, the header " +
                                   std::to_string(header.size()));
    for (std::size_t c = 0; c < cells.size(); ++c) {
      char* end = nullptr;
      double v = std::strtod(cells[c].c_str(), &end);
      cols[c].push_back(end != cells[c].c_str() ? v : std::nan(""));
    }
  }
  auto col = [&](const std::string& name) -> const std::vector<double>& {
    for (std::size_t c = 0; c < header.size(); ++c)
      if (header[c] == name) return cols[c];
    throw InputError("no column '" + name + "' in " + a.input);
  };
  if (!a.labels.empty() && a.labels.size() != a.y.size())
    throw InputError("--label needs one name per --y column");
  if (!a.styles.empty() && a.styles.size() != a.y.size())
    throw InputError("--style needs one style per --y column");
  Plot p;
  p.title = a.title;
  p.x.label = a.xlabel.empty() ? a.x : a.xlabel;
  p.y.label = a.ylabel;
  p.x.scale = a.logx ? AxisScale::Log : AxisScale::Linear;
  p.y.scale = a.logy ? AxisScale::Log : AxisScale::Linear;
  const auto& xs = col(a.x);
  for (std::size_t i = 0; i < a.y.size(); ++i)
    p.add(PlotSeries(xs, col(a.y[i]), a.labels.empty() ? a.y[i] : a.labels[i],
                     a.styles.empty() ? PlotStyle::LineMarkers : style_of(a.styles[i])));
  p.write(a.output);
}

}  // namespace

void register_plot(CLI::App& app) {
  auto a = std::make_shared<PlotArgs>();
  auto* cmd = app.add_subcommand("plot", "Plot columns of a CSV file (PNG or SVG)");
  cmd->footer(
      "The first non-comment line of the CSV names the columns; '#' lines are comments.\n\n"
      "Example:\n"
      "  microbrdf plot sweep.csv --x sigma_um --y measured,theory --style markers,line \\\n"
      "      --xlabel 'filter sigma (um)' --ylabel 'rms slope' -o sweep.png");
  cmd->add_option("csv", a->input, "CSV file with a header line")->required();
  cmd->add_option("-o,--output", a->output, "Plot (.png or .svg)")->required();
  cmd->add_option("--x", a->x, "Column for the abscissa")->required();
  cmd->add_option("--y", a->y, "Columns to plot, comma separated")->delimiter(',')->required();
  cmd->add_option("--label", a->labels, "Legend names for the --y columns")->delimiter(',');
  cmd->add_option("--style", a->styles, "line|dashed|dotted|markers|linemarkers per --y column")
      ->delimiter(',');
  cmd->add_option("--title", a->title, "Plot title");
  cmd->add_option("--xlabel", a->xlabel, "x axis label (with unit)");
  cmd->add_option("--ylabel", a->ylabel, "y axis label (with unit)");
  cmd->add_flag("--logx", a->logx, "Logarithmic x axis");
  cmd->add_flag("--logy", a->logy, "Logarithmic y axis");
  cmd->callback([a] { run_guarded("plot", [&] { run(*a); }); });
}

}  // namespace microbrdf::cli
