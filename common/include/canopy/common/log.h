// stderr logging: every line is prefixed with the tool name. One line per phase with
// counts and seconds (Phase). Progress is drawn only when stderr is a terminal.
#pragma once

#include <chrono>
#include <cstddef>
#include <string>

namespace canopy::common::log {

enum class Level { kQuiet = 0, kInfo = 1, kDebug = 2 };

void set_tool(const std::string& name);
const std::string& tool();
void set_level(Level level);
Level level();

void info(const std::string& message);   // shown unless -q
void debug(const std::string& message);  // shown with -v
void warn(const std::string& message);   // always shown ("<tool>: warning: ...")

// Times one phase; done() logs "<tool>: <phase>: <summary> (<seconds> s)" (no "<phase>: " when it is <tool>).
class Phase {
 public:
  explicit Phase(std::string name);
  double seconds() const;
  void done(const std::string& summary);

 private:
  std::string name_;
  std::chrono::steady_clock::time_point start_;
};

// Terminal-only progress counter ("<tool>: <what> 37/120"), erased when finished.
class Progress {
 public:
  Progress(std::string what, std::size_t total);
  ~Progress();
  void tick(std::size_t n = 1);

 private:
  std::string what_;
  std::size_t total_;
  std::size_t count_ = 0;
  bool enabled_;
};

}  // namespace canopy::common::log
