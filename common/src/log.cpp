#include "canopy/common/log.h"

#include <unistd.h>

#include <cstdio>
#include <iostream>

namespace canopy::common::log {
namespace {

std::string g_tool = "canopy";
Level g_level = Level::kInfo;

void emit(const std::string& line) {
  std::string out = g_tool + ": " + line + "\n";
  std::fwrite(out.data(), 1, out.size(), stderr);
  std::fflush(stderr);
}

}  // namespace

void set_tool(const std::string& name) { g_tool = name; }
const std::string& tool() { return g_tool; }
void set_level(Level level) { g_level = level; }
Level level() { return g_level; }

void info(const std::string& message) {
  if (g_level >= Level::kInfo) emit(message);
}
void debug(const std::string& message) {
  if (g_level >= Level::kDebug) emit(message);
}
void warn(const std::string& message) { emit("warning: " + message); }

Phase::Phase(std::string name) : name_(std::move(name)), start_(std::chrono::steady_clock::now()) {}

double Phase::seconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void Phase::done(const std::string& summary) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", seconds());
  // A phase named as its tool (detect's "detect", cocone's "cocone", classify's "classify") is
  // not said twice: "detect: density ..." rather than "detect: detect: density ..." (stop 70).
  info((name_ == g_tool ? std::string() : name_ + ": ") + summary + " (" + buf + " s)");
}

Progress::Progress(std::string what, std::size_t total)
    : what_(std::move(what)), total_(total), enabled_(g_level >= Level::kInfo && isatty(STDERR_FILENO) == 1) {}

Progress::~Progress() {
  if (enabled_ && count_ > 0) std::fputs("\r\033[K", stderr);
}

void Progress::tick(std::size_t n) {
  count_ += n;
  if (!enabled_) return;
  std::fprintf(stderr, "\r%s: %s %zu/%zu", g_tool.c_str(), what_.c_str(), count_, total_);
  std::fflush(stderr);
}

}  // namespace canopy::common::log
