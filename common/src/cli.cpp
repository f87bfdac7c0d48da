#include "canopy/common/cli.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <iostream>
#include <new>

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

const char* const kStandard[] = {"help", "version", "verbose", "quiet", "config",
                                 "threads", "seed", "input", "output"};

}  // namespace

Tool::Tool(std::string name, std::string description, bool random)
    : name_(std::move(name)), app_(std::move(description), name_), random_(random) {
  app_.set_help_flag("-h,--help", "print this help and exit");
  app_.set_version_flag("--version", name_ + " (canopy) " CANOPY_VERSION);
  app_.set_config("--config", "", "INI file of option values (keys: long option names)");
  app_.allow_config_extras(false);
  app_.add_flag_callback("-v,--verbose", [] { log::set_level(log::Level::kDebug); },
                         "log every detail to stderr");
  app_.add_flag_callback("-q,--quiet", [] { log::set_level(log::Level::kQuiet); },
                         "log only warnings and errors");
  app_.add_option("--threads", threads_, "worker threads")
      ->capture_default_str()
      ->check(CLI::Range(1, 256));
  if (random_) {
    app_.add_option("--seed", seed_, "random seed; same seed, same output")->capture_default_str();
  }
  app_.get_formatter()->column_width(34);
}

CLI::Option* Tool::add_input(std::string* path, const std::string& what) {
  input_ = path;
  return app_.add_option("-i,--input", *path, what + " ('-' = stdin)")->capture_default_str();
}

CLI::Option* Tool::add_output(std::string* path, const std::string& what) {
  return app_.add_option("-o,--output", *path, what + " ('-' = stdout)")->capture_default_str();
}

CLI::Option* Tool::add_length(const std::string& flags, double* metres, const std::string& help) {
  auto* opt = app_.add_option_function<std::string>(
      flags, [metres](const std::string& text) { *metres = parse_length(text); },
      help + " (length: 128mm, 12.8cm, 0.128m; bare = m)");
  opt->default_str(format_length(*metres));
  opt->type_name("LENGTH");
  return opt;
}

CLI::Option* Tool::add_angle(const std::string& flags, double* radians, const std::string& help) {
  auto* opt = app_.add_option_function<std::string>(
      flags, [radians](const std::string& text) { *radians = parse_angle(text); },
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

int Tool::run(int argc, char** argv, const std::function<void()>& body) {
  log::set_tool(name_);
  if (argc <= 1 && input_ != nullptr && !stdin_has_data()) {
    std::cerr << app_.help() << name_ << ": error: no input: give -i FILE or pipe data in\n";
    return 2;
  }
  try {
    app_.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app_.exit(e);  // --help, --version
    std::cerr << name_ << ": error: " << e.what() << "\n"
              << "Run '" << name_ << " --help' for the options.\n";
    return 2;
  } catch (const Error& e) {
    std::cerr << name_ << ": error: " << e.what() << "\n";
    return 2;  // a malformed value inside an option callback is a usage error
  }
  try {
    if (input_ != nullptr && *input_ == "-" && isatty(STDIN_FILENO) == 1) {
      throw UsageError("no input: stdin is a terminal; give -i FILE or pipe data in");
    }
    body();
    return 0;
  } catch (const Error& e) {
    std::cerr << name_ << ": error: " << e.what() << "\n";
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
