#include "canopy/common/cli.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <new>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/common/units.h"

namespace canopy::common {
namespace {

// True when stdin can carry data: a pipe, a socket or a redirected regular file.
// A terminal, /dev/null or a closed descriptor cannot.
bool stdin_has_data() {
  struct stat st {};
  if (fstat(STDIN_FILENO, &st) != 0) return false;
  return S_ISFIFO(st.st_mode) || S_ISREG(st.st_mode) || S_ISSOCK(st.st_mode);
}

const char* const kStandard[] = {"help",    "version", "verbose", "quiet", "config",
                                 "threads", "seed",    "input",   "output"};

// Edit distance with adjacent transpositions counted as one edit ("--vxoel" -> "--voxel": 1).
std::size_t edit_distance(const std::string& a, const std::string& b) {
  const std::size_t n = a.size(), m = b.size();
  std::vector<std::vector<std::size_t>> d(n + 1, std::vector<std::size_t>(m + 1));
  for (std::size_t i = 0; i <= n; ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= m; ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= n; ++i) {
    for (std::size_t j = 1; j <= m; ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
      }
    }
  }
  return d[n][m];
}

// Every option spelling ("--voxel", "-i") of an app and of its parsed subcommands.
void option_names(const CLI::App* app, std::vector<std::string>* out) {
  for (const CLI::Option* opt : app->get_options()) {
    for (const auto& l : opt->get_lnames()) out->push_back("--" + l);
    for (const auto& s : opt->get_snames()) out->push_back("-" + s);
  }
  for (const CLI::App* sub : app->get_subcommands()) option_names(sub, out);
}

// The closest option to a mistyped one, or "" when none is close: one edit for names up to
// four letters, two beyond; or the only option the word begins.
std::string closest_option(const std::string& given, const std::vector<std::string>& names) {
  std::string best;
  std::size_t best_d = std::string::npos;
  const std::size_t dashes = given.find_first_not_of('-');
  const std::string bare = dashes == std::string::npos ? given : given.substr(dashes);
  for (const auto& name : names) {
    const std::string nb = name.substr(name.find_first_not_of('-'));
    const std::size_t d = edit_distance(bare, nb);
    if (d < best_d) best_d = d, best = name;
  }
  const std::size_t limit = bare.size() <= 4 ? 1 : 2;
  if (best_d != std::string::npos && best_d <= limit && best_d < bare.size()) return best;
  std::string prefixed;
  int count = 0;
  for (const auto& name : names) {
    if (given.size() >= 3 && name.size() > given.size() && name.compare(0, given.size(), given) == 0) {
      prefixed = name;
      ++count;
    }
  }
  return count == 1 ? prefixed : "";
}

// f(), its UsageError prefixed with the option's name ("--sigma: '8 mm': no space ...").
template <typename F>
double named(const std::string& option, F&& f) {
  try {
    return f();
  } catch (const UsageError& e) { throw UsageError(option + ": " + e.what()); }
}

// The line of a --config file that CLI11 could not take as one value of KEY ("sigma"; "" = a
// [section] line), as "FILE: line N: TEXT: CAUSE"; "" when no line explains it.
std::string config_line_problem(const std::string& files, const std::string& key) {
  std::vector<std::pair<int, std::string>> lines;  // (number, text) of KEY's lines or sections
  std::string file;
  for (std::size_t start = 0; start <= files.size() && lines.empty();) {
    const std::size_t comma = files.find(", ", start);
    file = files.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    std::ifstream in(file);
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
      const std::size_t b = line.find_first_not_of(" \t");
      if (b == std::string::npos) continue;
      const std::string t = line.substr(b);
      if (key.empty()) {
        if (t[0] == '[') lines.emplace_back(n, t);
        continue;
      }
      const std::size_t eq = t.find('=');
      if (eq == std::string::npos) continue;
      std::string k = t.substr(0, eq);
      k.erase(k.find_last_not_of(" \t") + 1);
      if (k == key || k == "--" + key) lines.emplace_back(n, t);
    }
    if (comma == std::string::npos) break;
    start = comma + 2;
  }
  if (lines.empty()) return "";
  const std::string at =
      "--config " + file + ": line " + std::to_string(lines[0].first) + ": " + lines[0].second;
  if (key.empty()) return at + ": sections are not used; give the keys (long option names) without one";
  if (lines.size() > 1) {
    return "--config " + file + ": key '" + key + "' given twice (lines " + std::to_string(lines[0].first) +
           " and " + std::to_string(lines[1].first) + ")";
  }
  std::string value = lines[0].second.substr(lines[0].second.find('=') + 1);
  value.erase(0, value.find_first_not_of(" \t"));
  if (value.find(';') != std::string::npos) {
    return at + ": ';' does not start a comment here (comments are lines starting with #)";
  }
  if (value.find_first_of(" \t") != std::string::npos) {
    return at + ": a blank inside the value (one word: e.g. 8mm, not 8 mm)";
  }
  return "";
}

// A --config problem in words that name the file and what is wrong with it (CLI11 says "INI
// was not able to parse KEY" and "FILE was not readable (missing?)"); "" for other errors.
std::string config_message(const CLI::App& app, const CLI::ParseError& e) {
  const std::string what = e.what();
  if (dynamic_cast<const CLI::FileError*>(&e) != nullptr) {
    const std::string tail = " was not readable (missing?)";
    if (what.size() <= tail.size() || what.compare(what.size() - tail.size(), tail.size(), tail) != 0)
      return "";
    const std::string file = what.substr(0, what.size() - tail.size());
    struct stat st {};
    if (stat(file.c_str(), &st) != 0) return "--config " + file + ": no such file";
    if (S_ISDIR(st.st_mode)) return "--config " + file + ": is a directory, not an INI file";
    return "--config " + file + ": not a regular file";
  }
  const CLI::Option* config = app.get_config_ptr();
  std::string files;
  if (config != nullptr) {
    for (const auto& f : config->results()) files += (files.empty() ? "" : ", ") + f;
  }
  if (dynamic_cast<const CLI::ArgumentMismatch*>(&e) != nullptr && !files.empty() && what.rfind("--", 0) == 0) {
    // "--sigma: At Most 1 required but received 2": a config value CLI11 split at blanks or
    // the key given twice.
    const std::string key = what.substr(2, what.find(':') - 2);
    return config_line_problem(files, key);
  }
  if (dynamic_cast<const CLI::ConfigError*>(&e) == nullptr) return "";
  const std::string lead = "INI was not able to parse ";
  if (what.compare(0, lead.size(), lead) != 0) return "--config " + files + ": " + what;
  const std::string key = what.substr(lead.size());
  if (key.find('.') != std::string::npos) {
    const std::string section = config_line_problem(files, "");
    if (!section.empty()) return section;
  }
  std::vector<std::string> names;
  for (const CLI::Option* opt : app.get_options()) {
    for (const auto& l : opt->get_lnames()) names.push_back("--" + l);
  }
  const std::string close = closest_option("--" + key, names);
  return "--config " + files + ": unknown key '" + key + "' (the keys are the long option names" +
         (close.empty() ? std::string(")") : "; did you mean " + close.substr(2) + "?)");
}

}  // namespace

namespace detail {

std::string check_integer(const std::string& text, bool is_signed, long long lo, unsigned long long hi) {
  std::size_t i = 0;
  if (!text.empty() && (text[0] == '+' || text[0] == '-')) i = 1;
  const bool digits = i < text.size() && std::all_of(text.begin() + static_cast<long>(i), text.end(),
                                                     [](char c) { return c >= '0' && c <= '9'; });
  if (!digits) return "'" + text + "' is not a whole decimal number";
  errno = 0;
  if (!is_signed) {
    if (text[0] == '-') return "'" + text + "' is negative; expected a number >= 0";
    const unsigned long long v = std::strtoull(text.c_str(), nullptr, 10);
    if (errno == ERANGE || v > hi) {
      return "'" + text + "' is out of range (at most " + std::to_string(hi) + ")";
    }
    return "";
  }
  const long long v = std::strtoll(text.c_str(), nullptr, 10);
  if (errno == ERANGE || v < lo || (v > 0 && static_cast<unsigned long long>(v) > hi)) {
    return "'" + text + "' is out of range (" + std::to_string(lo) + " to " + std::to_string(hi) + ")";
  }
  return "";
}

std::string check_real(const std::string& text) {
  const std::size_t n = decimal_prefix(text);
  if (n == 0 || n != text.size()) return "'" + text + "' is not a decimal number";
  return decimal_problem(text);
}

}  // namespace detail

Tool::Tool(std::string name, std::string description, bool random)
    : name_(std::move(name)), app_(std::move(description), name_), random_(random) {
  app_.set_help_flag("-h,--help", "print this help and exit");
  app_.set_version_flag("--version", name_ + " (canopy) " CANOPY_VERSION);
  app_.set_config("--config", "", "INI file of option values (keys: long option names)");
  app_.allow_config_extras(false);
  app_.add_flag_callback(
      "-v,--verbose", [] { log::set_level(log::Level::kDebug); }, "log every detail to stderr");
  app_.add_flag_callback(
      "-q,--quiet", [] { log::set_level(log::Level::kQuiet); }, "log only warnings and errors");
  app_.add_option("--threads", threads_, "worker threads")
      ->capture_default_str()
      ->check(number_check<int>())
      ->check(CLI::Range(1, 256));
  if (random_) {
    app_.add_option("--seed", seed_, "random seed; same seed, same output")
        ->capture_default_str()
        ->check(number_check<std::uint64_t>());
  }
  app_.get_formatter()->column_width(34);
}

CLI::Option* Tool::add_input(std::string* path, const std::string& what) {
  input_ = path;
  return app_.add_option("-i,--input", *path, what + " ('-' = stdin)")->capture_default_str();
}

CLI::Option* Tool::add_output(std::string* path, const std::string& what) {
  outputs_.emplace_back("-o", path);
  return app_.add_option("-o,--output", *path, what + " ('-' = stdout)")->capture_default_str();
}

CLI::Option* Tool::add_output(const std::string& flags, std::string* path, const std::string& help) {
  CLI::Option* opt = app_.add_option(flags, *path, help)->capture_default_str();
  outputs_.emplace_back(opt->get_name(), path);
  return opt;
}

void Tool::without_threads() {
  if (CLI::Option* opt = app_.get_option_no_throw("--threads")) app_.remove_option(opt);
}

CLI::Option* Tool::add_length(const std::string& flags, double* metres, const std::string& help,
                              double warn_above) {
  const std::size_t comma = flags.find_last_of(',');
  const std::string name = comma == std::string::npos ? flags : flags.substr(comma + 1);
  const double usual = *metres;
  auto* opt = app_.add_option_function<std::string>(
      flags,
      [this, metres, warn_above, usual, name](const std::string& text) {
        *metres = length_value(name, text, usual, warn_above);
      },
      help + " (length: 128mm, 12.8cm, 0.128m; bare = m)");
  opt->default_str(format_length(*metres));
  opt->type_name("LENGTH");
  return opt;
}

double Tool::length_value(const std::string& name, const std::string& text, double usual, double warn_above) {
  const double metres = named(name, [&] { return parse_length(text); });
  const bool bare = decimal_prefix(text) == text.size();
  if (bare && metres >= 1 && usual < 1) bare_metres_.emplace_back(name, text);
  // Up to 1000 x the bound, where the value read as millimetres would be within it.
  if (warn_above > 0 && metres > warn_above && metres <= 1000 * warn_above) {
    log::warn(name + " " + text + " is " + format_length(metres) +
              (bare ? " (bare numbers are metres): did you mean " + text + "mm?"
                    : ", over " + format_length(warn_above) + ": is that intended?"));
  } else if (bare && usual > 0 && usual < 1 && metres / 1000 >= usual / 10 && metres / 1000 <= usual * 10) {
    // A default under 1 m, and the number read as millimetres within a decade of it (so read
    // as metres it is >= 100 x the default): most likely millimetres without the unit.
    log::warn(name + " " + text + " is " + format_length(metres) +
              " (bare numbers are metres; the default is " + format_length(usual) + "): did you mean " +
              text + "mm?");
  }
  return metres;
}

// A usage error that names an option (default under 1 m) given as a bare number of >= 1 m says it was read as
// metres (ncut --radius 512: "must be in [1mm, 100m]" alone does not say why).
std::string Tool::with_metres_hint(const std::string& message) const {
  for (const auto& [name, text] : bare_metres_) {
    for (std::size_t at = message.find(name); at != std::string::npos; at = message.find(name, at + 1)) {
      const std::size_t end = at + name.size();
      const bool whole =
          end == message.size() || !(std::isalnum(static_cast<unsigned char>(message[end])) != 0 ||
                                     message[end] == '-' || message[end] == '_');
      if (whole)
        return message + " (" + name + " " + text + " was read as " + text + " m: bare numbers are metres)";
    }
  }
  return message;
}

CLI::Option* Tool::add_angle(const std::string& flags, double* radians, const std::string& help) {
  const std::size_t comma = flags.find_last_of(',');
  const std::string name = comma == std::string::npos ? flags : flags.substr(comma + 1);
  auto* opt = app_.add_option_function<std::string>(
      flags,
      [radians, name](const std::string& text) { *radians = named(name, [&] { return parse_angle(text); }); },
      help + " (angle: 10deg, 0.17rad; bare = deg)");
  opt->default_str(format_angle(*radians));
  opt->type_name("ANGLE");
  return opt;
}

std::vector<std::pair<std::string, std::string>> Tool::parameters() const {
  std::vector<std::pair<std::string, std::string>> out;
  for (const CLI::Option* opt : app_.get_options()) {
    const std::string name = opt->get_single_name();
    if (name.empty() || std::find(std::begin(kStandard), std::end(kStandard), name) != std::end(kStandard)) {
      continue;
    }
    std::string value;
    if (opt->count() > 0) {
      for (const auto& r : opt->results()) value += (value.empty() ? "" : ",") + r;
    } else {
      value = opt->get_default_str();
    }
    out.emplace_back(name, value);
  }
  if (random_) out.emplace_back("seed", std::to_string(seed_));
  std::sort(out.begin(), out.end());
  return out;
}

// The message for arguments CLI11 could not place: the first one in command-line order.
std::string Tool::usage_message(int argc, char** argv) const {
  const std::vector<std::string> extras = app_.remaining(true);
  std::string first;
  for (int k = 1; k < argc && first.empty(); ++k) {
    if (std::find(extras.begin(), extras.end(), argv[k]) != extras.end()) first = argv[k];
  }
  if (first.empty() && !extras.empty()) first = extras.front();
  if (first.size() > 1 && first[0] == '-') {
    const std::string given = first.substr(0, first.find('='));
    std::vector<std::string> names;
    option_names(&app_, &names);
    const std::string close = closest_option(given, names);
    return "unknown option '" + given + "'" + (close.empty() ? "" : ": did you mean " + close + "?");
  }
  if (!app_.get_subcommands({}).empty()) {
    std::vector<std::string> subs;
    for (const CLI::App* sub : app_.get_subcommands({})) subs.push_back(sub->get_name());
    const std::string close = closest_option(first, subs);
    if (!close.empty()) return "unknown subcommand '" + first + "': did you mean " + close + "?";
  }
  if (input_ != nullptr) {
    const CLI::Option* in = app_.get_option_no_throw("--input");
    if (in != nullptr && in->count() > 0) {
      return "unexpected argument '" + first + "': one input only, given with -i";
    }
    return "unexpected argument '" + first + "': use -i " + first;
  }
  return "unexpected argument '" + first + "'";
}

int Tool::run(int argc, char** argv, const std::function<void()>& body) {
  log::set_tool(name_);
  if (argc <= 1 && input_ != nullptr && !stdin_has_data()) {
    std::cerr << app_.help() << name_ << ": error: no input: give -i FILE or pipe data in\n";
    return 2;
  }
  try {
    app_.parse(argc, argv);
  } catch (const CLI::ExtrasError&) {
    std::cerr << name_ << ": error: " << usage_message(argc, argv) << "\n"
              << "Run '" << name_ << " --help' for the options.\n";
    return 2;
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app_.exit(e);  // --help, --version
    // A mistyped option also makes a required one missing: name the mistyped one.
    if (!app_.remaining(true).empty()) {
      std::cerr << name_ << ": error: " << usage_message(argc, argv) << "\n"
                << "Run '" << name_ << " --help' for the options.\n";
      return 2;
    }
    const std::string config = config_message(app_, e);
    std::cerr << name_ << ": error: " << (config.empty() ? std::string(e.what()) : config) << "\n"
              << "Run '" << name_ << " --help' for the options.\n";
    return 2;
  } catch (const Error& e) {
    std::cerr << name_ << ": error: " << with_metres_hint(e.what()) << "\n";
    return 2;  // a malformed value inside an option callback is a usage error
  }
  try {
    if (input_ != nullptr && *input_ == "-" && isatty(STDIN_FILENO) == 1) {
      throw UsageError("no input: stdin is a terminal; give -i FILE or pipe data in");
    }
    // Outputs are checked before any work: a missing directory fails now, not after minutes.
    OutputSet outputs;
    for (const auto& [option, path] : outputs_) {
      if (!path->empty()) outputs.add(*path, option);
    }
    body();
    return 0;
  } catch (const Error& e) {
    std::cerr << name_
              << ": error: " << (e.exit_code() == 2 ? with_metres_hint(e.what()) : std::string(e.what()))
              << "\n";
    return e.exit_code();
  } catch (const std::bad_alloc&) {
    std::cerr << name_ << ": error: out of memory\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << name_ << ": error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace canopy::common
