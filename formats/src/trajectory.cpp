#include "canopy/formats/trajectory.h"

#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <stdexcept>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/common/units.h"

namespace canopy::formats {

namespace {

constexpr const char* kFirstLine = "# canopy trajectory 1";
constexpr std::array<const char*, 7> kColumns{"time", "x", "y", "z", "roll", "pitch", "heading"};

std::string at_line(std::size_t lineno) { return "line " + std::to_string(lineno) + ": "; }

// File text quoted in a message: at most 40 characters, non-printable bytes as \xNN.
std::string quoted(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size() && i < 40; ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02X", c);
      out += buf;
    }
  }
  if (s.size() > 40) out += "...";
  return out;
}

std::vector<std::string> words(const std::string& line) {
  std::vector<std::string> w;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const std::size_t b = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > b) w.push_back(line.substr(b, i - b));
  }
  return w;
}

bool blank(const std::string& line) { return line.find_first_not_of(" \t") == std::string::npos; }

bool comment(const std::string& line) {
  const std::size_t i = line.find_first_not_of(" \t");
  return i != std::string::npos && line[i] == '#';
}

double number(const std::string& word, const char* column, std::size_t lineno, const std::string& name) {
  const std::size_t n = common::decimal_prefix(word);
  if (n == 0 || n != word.size()) {
    throw common::DataError(name,
                            at_line(lineno) + column + " '" + quoted(word) + "' is not a decimal number");
  }
  const std::string problem = common::decimal_problem(word);
  if (!problem.empty()) throw common::DataError(name, at_line(lineno) + column + ": " + problem);
  return std::strtod(word.c_str(), nullptr);
}

// Shortest decimal that reads back to the same double (std::to_chars, round-trip exact).
std::string shortest(double v) {
  std::array<char, 64> buf{};
  const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  return std::string(buf.data(), r.ptr);
}

// a + (b - a) * f for angles in degrees along the shorter arc.
double lerp_angle(double a, double b, double f) {
  double d = std::fmod(b - a, 360.0);
  if (d > 180) d -= 360;
  if (d <= -180) d += 360;
  double v = std::fmod(a + d * f, 360.0);
  if (v > 180) v -= 360;
  if (v <= -180) v += 360;
  return v;
}

std::size_t segment(const Trajectory& t, double time, double tolerance, const std::string& name) {
  if (t.samples.empty()) throw common::DataError(name, "trajectory has no samples");
  const double t0 = t.samples.front().time;
  const double t1 = t.samples.back().time;
  if (!std::isfinite(time) || time < t0 - tolerance || time > t1 + tolerance) {
    throw common::DataError(name, "GPS time " + shortest(time) + " s is outside the trajectory's span [" +
                                      shortest(t0) + ", " + shortest(t1) + "] s by more than the tolerance " +
                                      shortest(tolerance) +
                                      " s (a trajectory of another flight or another time base?)");
  }
  // First sample with time > `time`; the segment is [i - 1, i].
  const auto it = std::upper_bound(t.samples.begin(), t.samples.end(), time,
                                   [](double v, const TrajectorySample& s) { return v < s.time; });
  return static_cast<std::size_t>(it - t.samples.begin());
}

}  // namespace

Trajectory parse_trajectory(const std::string& text, const std::string& name) {
  Trajectory t;
  std::size_t lineno = 0;
  std::size_t pos = 0;
  bool header = false;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    ++lineno;
    if (end - pos > kTrajectoryMaxLine) {
      throw common::DataError(name, at_line(lineno) + "longer than " + std::to_string(kTrajectoryMaxLine) +
                                        " characters (not a canopy trajectory)");
    }
    std::string line = text.substr(pos, end - pos);
    pos = end + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find('\0') != std::string::npos) {
      throw common::DataError(name,
                              at_line(lineno) + "holds a NUL byte (a binary file, not a canopy trajectory)");
    }
    if (lineno == 1) {
      if (line != kFirstLine) {
        throw common::DataError(name, at_line(1) + "'" + quoted(line) + "' is not '" + kFirstLine +
                                          "' (not a canopy trajectory, or another version)");
      }
      continue;
    }
    if (blank(line)) continue;
    if (comment(line)) {
      if (header) continue;
      const std::size_t i = line.find('#') + 1;
      std::string c = line.substr(i < line.size() && line[i] == ' ' ? i + 1 : i);
      // CRs before the line end (one is the CRLF's, taken above) are line-end debris, not text:
      // kept, the writer could not write the comment back (fuzz_trajectory finding).
      while (!c.empty() && c.back() == '\r') c.pop_back();
      t.comments.push_back(std::move(c));
      continue;
    }
    const std::vector<std::string> w = words(line);
    if (!header) {
      bool ok = w.size() == kColumns.size();
      for (std::size_t i = 0; ok && i < w.size(); ++i) ok = w[i] == kColumns[i];
      if (!ok) {
        throw common::DataError(name, at_line(lineno) + "'" + quoted(line) +
                                          "' is not the header line 'time x y z roll pitch heading'");
      }
      header = true;
      continue;
    }
    if (w.size() != kColumns.size()) {
      throw common::DataError(name, at_line(lineno) + std::to_string(w.size()) +
                                        " values; a sample has 7: time x y z roll pitch heading");
    }
    TrajectorySample s;
    double* fields[7] = {&s.time, &s.x, &s.y, &s.z, &s.roll, &s.pitch, &s.heading};
    for (std::size_t i = 0; i < w.size(); ++i) *fields[i] = number(w[i], kColumns[i], lineno, name);
    if (!t.samples.empty() && !(s.time > t.samples.back().time)) {
      throw common::DataError(name, at_line(lineno) + "time " + w[0] + " is not after the previous sample's " +
                                        shortest(t.samples.back().time) + " (times must strictly increase)");
    }
    t.samples.push_back(s);
  }
  if (lineno == 0) throw common::DataError(name, "empty file (not a canopy trajectory)");
  if (!header) throw common::DataError(name, "no header line 'time x y z roll pitch heading'");
  if (t.samples.empty()) throw common::DataError(name, "no samples");
  return t;
}

Trajectory read_trajectory(const std::string& path) {
  const std::string name = common::display_name(path);
  std::string text;
  std::array<char, 1 << 16> block;
  auto slurp = [&](std::istream& in) {
    while (in.read(block.data(), block.size()) || in.gcount() > 0) {
      text.append(block.data(), static_cast<std::size_t>(in.gcount()));
      if (text.size() > kTrajectoryMaxBytes) {
        throw common::DataError(name, "larger than " + std::to_string(kTrajectoryMaxBytes >> 20) +
                                          " MiB (canopy's bound on a trajectory file)");
      }
    }
    if (in.bad()) throw common::DataError(name, "read error");
  };
  if (path == "-") {
    slurp(std::cin);
  } else {
    struct stat st {};
    if (stat(path.c_str(), &st) != 0)
      throw common::DataError(name, std::string("cannot open: ") + std::strerror(errno));
    if (S_ISDIR(st.st_mode)) throw common::DataError(name, "is a directory, not a trajectory file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw common::DataError(name, std::string("cannot open: ") + std::strerror(errno));
    slurp(in);
  }
  return parse_trajectory(text, name);
}

std::string serialize_trajectory(const Trajectory& t) {
  std::string out = std::string(kFirstLine) + "\n";
  for (const std::string& c : t.comments) {
    // A trailing CR would be read back as part of the line end: refused like a line break.
    if (c.find('\n') != std::string::npos || (!c.empty() && c.back() == '\r') ||
        c.find('\0') != std::string::npos) {
      throw std::invalid_argument("trajectory comment holds a line break or a NUL");
    }
    out += "# " + c + "\n";
  }
  out += "time x y z roll pitch heading\n";
  for (std::size_t i = 0; i < t.samples.size(); ++i) {
    const TrajectorySample& s = t.samples[i];
    const double v[7] = {s.time, s.x, s.y, s.z, s.roll, s.pitch, s.heading};
    for (int k = 0; k < 7; ++k) {
      if (!std::isfinite(v[k]))
        throw std::invalid_argument("trajectory sample " + std::to_string(i) + ": non-finite value");
      out += shortest(v[k] == 0 ? 0.0 : v[k]);  // no "-0" (the reader refuses negative zero)
      out += k < 6 ? ' ' : '\n';
    }
    if (i > 0 && !(s.time > t.samples[i - 1].time)) {
      throw std::invalid_argument("trajectory sample " + std::to_string(i) + ": time not after the previous");
    }
  }
  return out;
}

void write_trajectory(const Trajectory& t, const std::string& path) {
  common::write_file_atomic(path, serialize_trajectory(t));
}

std::array<double, 3> trajectory_position(const Trajectory& t, double time, double tolerance,
                                          const std::string& name) {
  const std::size_t i = segment(t, time, tolerance, name);
  if (i == 0) return {t.samples.front().x, t.samples.front().y, t.samples.front().z};
  if (i == t.samples.size()) return {t.samples.back().x, t.samples.back().y, t.samples.back().z};
  const TrajectorySample& a = t.samples[i - 1];
  const TrajectorySample& b = t.samples[i];
  const double f = (time - a.time) / (b.time - a.time);
  return {a.x + (b.x - a.x) * f, a.y + (b.y - a.y) * f, a.z + (b.z - a.z) * f};
}

TrajectorySample trajectory_sample(const Trajectory& t, double time, double tolerance, const std::string& name) {
  const std::size_t i = segment(t, time, tolerance, name);
  TrajectorySample s;
  if (i == 0 || i == t.samples.size()) {
    s = i == 0 ? t.samples.front() : t.samples.back();
    s.heading = lerp_angle(s.heading, s.heading, 0);
  } else {
    const TrajectorySample& a = t.samples[i - 1];
    const TrajectorySample& b = t.samples[i];
    const double f = (time - a.time) / (b.time - a.time);
    s.x = a.x + (b.x - a.x) * f;
    s.y = a.y + (b.y - a.y) * f;
    s.z = a.z + (b.z - a.z) * f;
    s.roll = lerp_angle(a.roll, b.roll, f);
    s.pitch = lerp_angle(a.pitch, b.pitch, f);
    s.heading = lerp_angle(a.heading, b.heading, f);
  }
  s.time = time;
  return s;
}

}  // namespace canopy::formats
