#include "canopy/documents/stage_time.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

#include "canopy/common/error.h"

namespace canopy::documents {

namespace {

constexpr std::streamsize kMaxBytes = 4096;  // a .time file is one short line

// One number of a .time file: the whole word, finite, >= 0.
double time_number(const std::string& word, const std::string& file, const char* what) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(word.c_str(), &end);
  if (word.empty() || end != word.c_str() + word.size() || errno == ERANGE || !std::isfinite(v) || v < 0) {
    throw common::DataError(file, std::string(what) + " '" + word + "' is not a finite number >= 0");
  }
  return v;
}

}  // namespace

StageTime read_stage_time(const std::string& artifact) {
  StageTime t;
  const std::string file = artifact + ".time";
  std::ifstream in(file, std::ios::binary);
  if (!in) return t;  // the stage did not run (or its .time was removed with a failed run)
  std::string text(static_cast<size_t>(kMaxBytes) + 1, '\0');
  in.read(text.data(), kMaxBytes + 1);
  if (in.bad()) throw common::DataError(file, "cannot read the stage's time file");
  text.resize(static_cast<size_t>(in.gcount()));
  if (in.gcount() > kMaxBytes) {
    throw common::DataError(file, "longer than " + std::to_string(kMaxBytes) +
                                      " bytes: not a stage time (wall seconds, peak KiB, user s, system s)");
  }
  std::istringstream words(text);
  std::vector<std::string> w;
  for (std::string s; words >> s;) w.push_back(s);
  if (w.size() != 2 && w.size() != 4) {
    throw common::DataError(file, "holds " + std::to_string(w.size()) +
                                      " words, not a stage time: wall seconds and peak KiB, then user and "
                                      "system CPU seconds (GNU time's %e %M %U %S)");
  }
  t.seconds = time_number(w[0], file, "wall time");
  t.peak_mb = time_number(w[1], file, "peak memory") / 1024.0;
  if (w.size() == 4) {
    t.user_seconds = time_number(w[2], file, "user CPU time");
    t.system_seconds = time_number(w[3], file, "system CPU time");
    t.has_cpu = true;
  }
  t.present = true;
  return t;
}

}  // namespace canopy::documents
