// The one command-line wrapper every canopy tool uses (CLI11 underneath).
//
// Standard options of every tool: -h/--help, --version, -v/--verbose, -q/--quiet,
// --config FILE (INI, keys = long option names, unknown keys rejected), --threads N,
// and --seed N for tools that draw random numbers.
//
//   int main(int argc, char** argv) {
//     canopy::common::Tool tool("fitvox", "Local surface fits in voxels.");
//     Params p;  std::string in = "-", out = "-";
//     tool.add_input(&in);  tool.add_output(&out);
//     tool.add_length("--voxel", &p.voxel, "voxel edge");
//     return tool.run(argc, argv, [&] { ... });
//   }
//
// run() parses (usage errors -> exit 2), then calls the body inside the single catch
// ladder: canopy::common::Error -> its exit code, std::exception -> 1, with
// "<tool>: error: <message>" on stderr.
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace canopy::common {

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
  // A length option: accepts 128mm / 12.8cm / 0.128m / bare metres; stores metres.
  CLI::Option* add_length(const std::string& flags, double* metres, const std::string& help);
  // An angle option: accepts 10deg / 0.17rad / bare degrees; stores radians.
  CLI::Option* add_angle(const std::string& flags, double* radians, const std::string& help);
  // Any other option, default shown in --help.
  template <typename T>
  CLI::Option* add(const std::string& flags, T* value, const std::string& help) {
    return app_.add_option(flags, *value, help)->capture_default_str();
  }
  CLI::Option* add_flag(const std::string& flags, bool* value, const std::string& help) {
    return app_.add_flag(flags, *value, help);
  }

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
};

}  // namespace canopy::common
