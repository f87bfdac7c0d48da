// The one command-line wrapper every canopy tool uses (CLI11 underneath).
//
// Standard options of every tool: -h/--help, --version, -v/--verbose, -q/--quiet,
// --config FILE (INI, keys = long option names, unknown keys rejected), --threads N (removed
// by without_threads() in tools that do not use threads), and --seed N for tools that draw
// random numbers.
//
//   int main(int argc, char** argv) {
//     canopy::common::Tool tool("fitvox", "Local surface fits in voxels.");
//     Params p;  std::string in = "-", out = "-";
//     tool.add_input(&in);  tool.add_output(&out);
//     tool.add_length("--voxel", &p.voxel, "voxel edge");
//     return tool.run(argc, argv, [&] { ... });
//   }
//
// run() parses (usage errors -> exit 2), checks every output registered with add_output
// (its directory exists and is writable, no two outputs are the same file: exit 1 / 2), then
// calls the body inside the single catch ladder: canopy::common::Error -> its exit code,
// std::exception -> 1, with "<tool>: error: <message>" on stderr.
//
// Parsing is strict: numbers are decimal (no hex, octal, inf or nan; integers without a
// sign where the type is unsigned, within the type's range), a stray word is answered with
// "use -i <word>", a mistyped option with "did you mean --<option>?".
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <limits>
#include <functional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace canopy::common {

namespace detail {
// "" when text is a decimal number of the kind (and range) asked for, else the problem.
std::string check_integer(const std::string& text, bool is_signed, long long lo, unsigned long long hi);
std::string check_real(const std::string& text);
}  // namespace detail

// The validator Tool::add attaches to numeric options (public for options added to
// subcommands through app()).
template <typename T>
CLI::Validator number_check() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        if constexpr (std::is_integral_v<T>) {
          return detail::check_integer(text, std::is_signed_v<T>,
                                       static_cast<long long>(std::numeric_limits<T>::min()),
                                       static_cast<unsigned long long>(std::numeric_limits<T>::max()));
        } else {
          return detail::check_real(text);
        }
      },
      "");
}

class Tool {
 public:
  Tool(std::string name, std::string description, bool random = false);

  CLI::App& app() { return app_; }
  const std::string& name() const { return name_; }

  // -i/--input (default "-": stdin). With no arguments at all and no data on stdin
  // (a terminal or /dev/null) the tool prints usage and exits 2.
  CLI::Option* add_input(std::string* path, const std::string& what = "input file");
  // -o/--output (default "-": stdout).
  CLI::Option* add_output(std::string* path, const std::string& what = "output file");
  // A further output option (e.g. "--colored"); an empty value means "not written".
  CLI::Option* add_output(const std::string& flags, std::string* path, const std::string& help);
  // A length option: accepts 128mm / 12.8cm / 0.128m / bare metres; stores metres. With
  // warn_above > 0, a value above it (metres) draws a warning ("bare numbers are metres").
  // Whatever warn_above, a bare number for an option whose default is under 1 m warns when
  // read as millimetres it would be within a decade of the default (length_value).
  CLI::Option* add_length(const std::string& flags, double* metres, const std::string& help,
                          double warn_above = 0);
  // TEXT parsed as a length for option NAME (its errors name it), with add_length's warnings
  // (usual = the option's default in metres, 0 = none); for options parsed by hand.
  double length_value(const std::string& name, const std::string& text, double usual, double warn_above = 0);
  // An angle option: accepts 10deg / 0.17rad / bare degrees; stores radians.
  CLI::Option* add_angle(const std::string& flags, double* radians, const std::string& help);
  // Any other option, default shown in --help.
  template <typename T>
  CLI::Option* add(const std::string& flags, T* value, const std::string& help) {
    CLI::Option* opt = app_.add_option(flags, *value, help)->capture_default_str();
    if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) opt->check(number_check<T>());
    return opt;
  }
  CLI::Option* add_flag(const std::string& flags, bool* value, const std::string& help) {
    return app_.add_flag(flags, *value, help);
  }

  // Removes --threads from a tool that does not use it.
  void without_threads();

  int threads() const { return threads_; }
  std::uint64_t seed() const { return seed_; }
  // (long option name, value as given or defaulted) of every option except the standard
  // ones and input/output, sorted by name: the parameter record of provenance blocks.
  std::vector<std::pair<std::string, std::string>> parameters() const;

  int run(int argc, char** argv, const std::function<void()>& body);

 private:
  std::string name_;
  CLI::App app_;
  bool random_;
  int threads_ = 1;
  std::uint64_t seed_ = 1;
  bool uses_stdin_ = false;
  std::string* input_ = nullptr;
  std::vector<std::pair<std::string, std::string*>> outputs_;     // (option, path)
  std::vector<std::pair<std::string, std::string>> bare_metres_;  // (option, bare number >= 1) given
  std::string with_metres_hint(const std::string& message) const;
  std::string usage_message(int argc, char** argv) const;
};

}  // namespace canopy::common
