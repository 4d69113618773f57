// Parse errors with suggestions (cli_parse_errors.hpp).
#include "cli_parse_errors.hpp"

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "microbrdf/distribute.hpp"

namespace microbrdf::cli {

std::size_t edit_distance(const std::string& a, const std::string& b) {
  // Damerau-Levenshtein (optimal string alignment), rows of the DP table.
  std::vector<std::size_t> prev2(b.size() + 1), prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        cur[j] = std::min(cur[j], prev2[j - 2] + 1);
    }
    prev2.swap(prev);
    prev.swap(cur);
  }
  return prev[b.size()];
}

namespace {

// The nearest of `names` to `word`, if near enough to be a slip (a third of its letters, at
// least 2), else "".
std::string nearest(const std::string& word, const std::vector<std::string>& names) {
  std::string best;
  std::size_t best_d = std::max<std::size_t>(2, word.size() / 3) + 1;
  for (const auto& n : names) {
    const std::size_t d = edit_distance(word, n);
    if (d < best_d) best_d = d, best = n;
  }
  return best;
}

// Long flags ("--name") of `app` and of its parents (their flags apply below them).
std::vector<std::string> flags_of(const CLI::App* app) {
  std::vector<std::string> out;
  for (; app; app = app->get_parent())
    for (const CLI::Option* o : app->get_options())
      for (const auto& l : o->get_lnames()) out.push_back("--" + l);
  return out;
}

// The option of `app` or of a parent that "--name" names, or nullptr.
CLI::Option* option_named(CLI::App* app, const std::string& flag) {
  for (; app; app = app->get_parent())
    for (CLI::Option* o : app->get_options())
      for (const auto& l : o->get_lnames())
        if ("--" + l == flag) return o;
  return nullptr;
}

// CLI11 stops at the first value a validator refuses. Every other "--flag value" on the line is
// put through its option's validators here too (in CLI11's order, each seeing what the one
// before left), so that all bad values are said at once: "--flag: problem" per refusal.
std::vector<std::string> refused_values(CLI::App* app, int argc, char** argv) {
  std::vector<std::string> out;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--") break;
    if (a.rfind("--", 0) != 0) continue;
    const std::size_t eq = a.find('=');
    const std::string flag = a.substr(0, eq);
    CLI::Option* o = option_named(app, flag);
    // Unknown, or a flag (it takes no value: expected 0).
    if (!o || o->get_expected_max() == 0) continue;
    std::string value;
    if (eq != std::string::npos)
      value = a.substr(eq + 1);
    else if (i + 1 < argc)
      value = argv[++i];
    else
      continue;
    // A delimited option (--wavelength 405nm,633nm) is validated item by item, as CLI11 does.
    std::vector<std::string> items;
    const char delim = o->get_delimiter();
    for (std::size_t at = 0;;) {
      const std::size_t end = delim ? value.find(delim, at) : std::string::npos;
      items.push_back(value.substr(at, end == std::string::npos ? end : end - at));
      if (end == std::string::npos) break;
      at = end + 1;
    }
    std::string problem;
    for (std::string item : items)
      for (int k = 0; problem.empty(); ++k) {
        CLI::Validator* v = nullptr;
        try {
          v = o->get_validator(k);
        } catch (const CLI::OptionNotFound&) {
          break;
        }
        try {
          problem = (*v)(item);
        } catch (const std::exception& e) {
          problem = e.what();
        }
      }
    if (!problem.empty()) out.push_back(flag + ": " + problem);
  }
  return out;
}

std::vector<std::string> subcommands_of(CLI::App* app) {
  std::vector<std::string> out;
  for (const CLI::App* s : app->get_subcommands([](CLI::App*) { return true; }))
    out.push_back(s->get_name());
  return out;
}

}  // namespace

int report_parse_error(CLI::App& app, const CLI::ParseError& e, int argc, char** argv) {
  if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
  if (!mpi_is_root()) return 2;
  // The deepest subcommand reached: its name prefixes the message, its flags are the candidates.
  CLI::App* cur = &app;
  std::string path = "microbrdf";
  std::vector<std::string> chain;
  for (auto subs = cur->get_subcommands(); !subs.empty(); subs = cur->get_subcommands()) {
    cur = subs.back();
    path += " " + cur->get_name();
    chain.push_back(cur->get_name());
  }
  if (argc <= 1) {
    std::fprintf(stderr,
                 "%s\nStart here: `make demo` runs the whole chain on bundled scans; on your own\n"
                 "height map: microbrdf info SCAN (is it read right?), then\n"
                 "microbrdf predict SCAN --metal Al -o report/ (NDFs, fits, renders, a report).\n"
                 "Every command has --help.\n",
                 app.help().c_str());
    return 2;
  }
  std::string message = e.what();
  // Every unknown flag at once, each with the nearest real one.
  const auto flags = flags_of(cur);
  std::vector<std::string> unknown;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--") break;
    if (a.rfind("--", 0) != 0) continue;
    a = a.substr(0, a.find('='));
    if (std::find(flags.begin(), flags.end(), a) == flags.end()) {
      const std::string n = nearest(a, flags);
      unknown.push_back(a + (n.empty() ? "" : " (did you mean " + n + "?)"));
    }
  }
  if (!unknown.empty()) {
    std::string said = unknown.size() == 1 ? "unknown flag " : "unknown flags ";
    for (std::size_t i = 0; i < unknown.size(); ++i) said += (i ? ", " : "") + unknown[i];
    // CLI11 stops at the first problem; the unknown flags come first, then what it found.
    message = dynamic_cast<const CLI::ExtrasError*>(&e) ? said : said + "; " + message;
  }
  // A refused value: every refused value of the line, not only the first CLI11 met.
  if (dynamic_cast<const CLI::ValidationError*>(&e) != nullptr) {
    const auto refused = refused_values(cur, argc, argv);
    if (refused.size() > 1) {
      std::string list;
      for (std::size_t i = 0; i < refused.size(); ++i) list += (i ? "; " : "") + refused[i];
      // (after the unknown flags, when there are any)
      const std::string before = unknown.empty() ? "" : message.substr(0, message.find("; ") + 2);
      message = before + std::to_string(refused.size()) + " values refused: " + list;
    }
  }
  // A missing or misspelt subcommand: the word after the last command given.
  const auto subs = subcommands_of(cur);
  const bool missing_or_extra = dynamic_cast<const CLI::RequiredError*>(&e) != nullptr ||
                                dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr;
  if (missing_or_extra && !subs.empty() && cur->get_subcommands().empty()) {
    int next = 1;
    for (int i = 1; i < argc && !chain.empty(); ++i)
      if (argv[i] == chain.back()) {
        next = i + 1;
        break;
      }
    std::string all;
    for (const auto& s : subs) all += (all.empty() ? "" : ", ") + s;
    const std::string word = next < argc ? argv[next] : "";
    if (!word.empty() && word[0] != '-') {
      const std::string n = nearest(word, subs);
      message = "unknown command '" + word + "'" +
                (n.empty() ? "" : " (did you mean '" + n + "'?)") + "; the commands: " + all;
    } else {
      message = "give a command: " + all;
    }
  }
  std::fprintf(stderr, "%s: error: %s\nRun '%s --help' for the options and examples.\n",
               path.c_str(), message.c_str(), path.c_str());
  return 2;
}

}  // namespace microbrdf::cli
