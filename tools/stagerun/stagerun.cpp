// The rules of the stage runner without processes or locks (stagerun.h). Each follows the bash
// of scripts/stage.sh it replaced, byte for byte in what it writes (docs/decisions/cost.md §19).
#include "stagerun/stagerun.h"

#include <sys/wait.h>

#include <algorithm>
#include <cinttypes>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <utility>

#include "canopy/formats/ini.h"

namespace canopy::stagerun {
namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\n'; }

bool all_digits(std::string_view s) {
  if (s.empty()) return false;
  for (char c : s) {
    if (c < '0' || c > '9') return false;
  }
  return true;
}

std::int64_t to_int(std::string_view digits) {
  std::int64_t v = 0;
  for (char c : digits) v = v * 10 + (c - '0');
  return v;
}

std::string format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
std::string format(const char* fmt, ...) {
  char buf[512];
  va_list ap;
  va_start(ap, fmt);
  const int n = std::vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  if (n < 0) return std::string();
  if (static_cast<std::size_t>(n) < sizeof buf) return std::string(buf, n);
  std::string out(static_cast<std::size_t>(n) + 1, '\0');
  va_start(ap, fmt);
  std::vsnprintf(out.data(), out.size(), fmt, ap);
  va_end(ap);
  out.resize(n);
  return out;
}

std::string_view trim(std::string_view s, const char* blanks) {
  const auto b = s.find_first_not_of(blanks);
  if (b == std::string_view::npos) return {};
  return s.substr(b, s.find_last_not_of(blanks) - b + 1);
}

// "D.CC" with exactly two decimals.
bool is_hundredths(std::string_view s) {
  const auto dot = s.find('.');
  return dot != std::string_view::npos && all_digits(s.substr(0, dot)) && s.size() == dot + 3 &&
         all_digits(s.substr(dot + 1));
}

}  // namespace

bool parse_ms(std::string_view text, std::int64_t* ms) {
  const auto dot = text.find('.');
  const std::string_view whole = text.substr(0, dot);
  const std::string_view frac = dot == std::string_view::npos ? std::string_view() : text.substr(dot + 1);
  if (!whole.empty() && !all_digits(whole)) return false;
  if (!frac.empty() && !all_digits(frac)) return false;
  if (whole.empty() && frac.empty()) return false;
  std::int64_t thousandths = 0;
  for (std::size_t i = 0; i < 3; ++i) thousandths = thousandths * 10 + (i < frac.size() ? frac[i] - '0' : 0);
  *ms = to_int(whole) * 1000 + thousandths;
  return true;
}

std::vector<std::string> read_fields(std::string_view line, int count) {
  std::vector<std::string> out(count);
  std::size_t i = 0;
  for (int f = 0; f < count; ++f) {
    while (i < line.size() && is_blank(line[i])) ++i;
    if (i == line.size()) break;
    if (f == count - 1) {
      out[f] = std::string(trim(line.substr(i), " \t\n"));
      break;
    }
    const std::size_t b = i;
    while (i < line.size() && !is_blank(line[i])) ++i;
    out[f] = std::string(line.substr(b, i - b));
  }
  return out;
}

std::string_view first_line(std::string_view text) { return text.substr(0, text.find('\n')); }

std::string stage_kind(std::string_view artifact, const std::vector<std::string>& command) {
  std::string_view tool = command.empty() ? std::string_view() : std::string_view(command.front());
  for (const auto& word : command) {
    if (word.find("/bin/") != std::string::npos) {
      tool = word;
      break;
    }
  }
  const auto slash = tool.rfind('/');
  if (slash != std::string_view::npos) tool.remove_prefix(slash + 1);
  std::string kind(tool);
  kind += ':';
  if (artifact.find("/cands/") != std::string_view::npos) kind += "cand/";
  const auto name_at = artifact.rfind('/');
  for (char c : artifact.substr(name_at == std::string_view::npos ? 0 : name_at + 1)) {
    kind += (c >= '0' && c <= '9') ? '#' : c;
  }
  return kind;
}

std::string time_file_text(const Usage& u) {
  std::string out;
  const int st = u.wait_status;
  if (WIFSTOPPED(st)) {
    out = format("Command stopped by signal %d\n", WSTOPSIG(st));
  } else if (WIFSIGNALED(st)) {
    out = format("Command terminated by signal %d\n", WTERMSIG(st));
  } else if (WIFEXITED(st) && WEXITSTATUS(st) != 0) {
    out = format("Command exited with non-zero status %d\n", WEXITSTATUS(st));
  }
  const auto secs = [](std::int64_t us) {
    return format("%" PRId64 ".%02" PRId64, us / 1000000, us % 1000000 / 10000);
  };
  out += secs(u.wall_us) + ' ' + std::to_string(u.max_rss_kib) + ' ' + secs(u.user_us) + ' ' +
         secs(u.sys_us) + '\n';
  return out;
}

int time_exit_status(int st) {
  if (WIFSTOPPED(st)) return 128 + WSTOPSIG(st);
  if (WIFSIGNALED(st)) return 128 + WTERMSIG(st);
  if (WIFEXITED(st)) return WEXITSTATUS(st);
  return 1;
}

std::string left_text(std::int64_t left_ms) {
  if (left_ms < 90000) return format("~%" PRId64 " s left", (left_ms + 500) / 1000);
  if (left_ms < 5400000) return format("~%" PRId64 " min left", (left_ms + 30000) / 60000);
  return format("~%" PRId64 " h %02" PRId64 " min left", left_ms / 3600000,
                (left_ms % 3600000 + 30000) / 60000);
}

bool is_wall_seconds(std::string_view previous) {
  const auto dot = previous.find('.');
  return all_digits(previous.substr(0, dot)) &&
         (dot == std::string_view::npos || previous.size() == dot + 1 || all_digits(previous.substr(dot + 1)));
}

ProgressStep progress_step(std::string_view state, std::string_view est, std::string_view previous,
                           std::string_view kind, std::int64_t now_ms) {
  ProgressStep step;
  const auto f = read_fields(first_line(state), 6);  // n m d e t0 rest
  std::int64_t d = 0, e = 0;
  if (!all_digits(f[0]) || !all_digits(f[1]) || f[4].empty() || !parse_ms(f[2], &d) || !parse_ms(f[3], &e)) {
    return step;
  }
  const std::int64_t n = to_int(f[0]) + 1;
  std::int64_t m = to_int(f[1]);
  // This stage's share: its artifact's previous wall time, else its kind's estimate, its tool's,
  // every stage's, else 1 s. (The estimates' lines are read as bash's `while read` did: a last
  // line without its newline is not read.)
  std::int64_t x = -1;
  if (is_wall_seconds(previous)) {
    parse_ms(previous, &x);
  } else {
    const std::string_view tool = kind.substr(0, kind.find(':'));
    std::string t, all;
    std::size_t at = 0;
    while (at < est.size()) {
      const auto nl = est.find('\n', at);
      if (nl == std::string_view::npos) break;
      const auto kv = read_fields(est.substr(at, nl - at), 3);
      at = nl + 1;
      if (kv[0] == kind) {
        if (!parse_ms(kv[1], &x)) x = -1;
      } else if (kv[0] == tool) {
        t = kv[1];
      } else if (kv[0] == "*") {
        all = kv[1];
      }
    }
    if (x < 0 && !parse_ms(t, &x) && !parse_ms(all, &x)) x = 1000;
  }
  d += x;
  if (m < n) m = n;
  if (e < d) e = d;
  step.valid = true;
  step.state_line = format("%" PRId64 " %" PRId64 " %" PRId64 ".%03" PRId64 " %" PRId64 ".%03" PRId64 " %s\n",
                           n, m, d / 1000, d % 1000, e / 1000, e % 1000, f[4].c_str());
  step.count = std::to_string(n) + '/' + std::to_string(m) + ' ';
  // (shown once 1% of the estimated work is done: before, the pace is mostly noise)
  std::int64_t t0 = 0;
  if (d > 0 && n < m && 100 * d >= e && parse_ms(f[4], &t0)) {
    const std::int64_t elapsed = now_ms - t0;
    if (elapsed >= 0) step.left = "  " + left_text(elapsed * (e - d) / d);
  }
  return step;
}

std::string failure_words(std::string_view how, int rc, bool* tool_failed) {
  // The tool's own failure: a status from 1 to 125. 126 and 127 are "cannot execute" and "not
  // found", 128 and more a signal passed on by a wrapper.
  constexpr std::string_view exited = "Command exited with non-zero status ";
  std::string status;
  if (how.substr(0, exited.size()) == exited) status = std::string(how.substr(how.rfind(' ') + 1));
  const std::int64_t s = all_digits(status) ? to_int(status) : -1;
  *tool_failed = s >= 0 && s <= 125;
  if (*tool_failed) return "exit " + status;
  if (!status.empty() && s <= 127) return "exit " + status + ", the command could not run";
  if (!status.empty()) return "exit " + status + ", a signal";
  if (!how.empty()) {
    constexpr std::string_view command = "Command ";
    return std::string(how.substr(0, command.size()) == command ? how.substr(command.size()) : how);
  }
  return "exit " + std::to_string(rc) + "; the tool did not finish";
}

std::string cpu_seconds(std::string_view time_line) {
  const auto f = read_fields(time_line, 4);  // secs kib user sys
  std::int64_t cs = 0;
  if (is_hundredths(f[2]) && is_hundredths(f[3])) {
    const auto hundredths = [](const std::string& s) {
      return to_int(s.substr(0, s.size() - 3)) * 100 + to_int(s.substr(s.size() - 2));
    };
    cs = hundredths(f[2]) + hundredths(f[3]);
  }
  return format("%" PRId64 ".%02" PRId64, cs / 100, cs % 100);
}

std::string done_line(std::string_view count, std::string_view artifact, std::string_view time_line,
                      std::string_view left) {
  const auto f = read_fields(time_line, 4);  // secs kib user sys
  const long double secs = std::strtold(f[0].c_str(), nullptr);
  const long double cpu_secs = std::strtold(cpu_seconds(time_line).c_str(), nullptr);
  const long long kib = std::strtoll(f[1].c_str(), nullptr, 10);
  return format("done  %.*s%-58.*s %7.2Lf s %7.2Lf cpu %6lld MB%.*s\n", static_cast<int>(count.size()),
                count.data(), static_cast<int>(artifact.size()), artifact.data(), secs, cpu_secs, kib / 1024,
                static_cast<int>(left.size()), left.data());
}

std::string indented_tail(std::string_view text, int count) {
  if (text.empty() || count <= 0) return std::string();
  // tail -n COUNT: the lines after the (COUNT+1)-th newline from the end, the file's last
  // newline ending its last line
  std::size_t end = text.size();
  if (text.back() == '\n') --end;
  std::size_t start = 0;
  int seen = 0;
  for (std::size_t i = end; i > 0; --i) {
    if (text[i - 1] == '\n' && ++seen == count) {
      start = i;
      break;
    }
  }
  std::string out;
  std::size_t at = start;
  while (at < text.size()) {
    std::size_t nl = text.find('\n', at);
    if (nl == std::string_view::npos) nl = text.size();
    out += "      ";
    out += text.substr(at, nl - at);
    out += '\n';
    at = nl + 1;
  }
  return out;
}

std::string last_log_line(std::string_view text, std::size_t max) {
  std::size_t end = text.size();
  while (end > 0) {
    std::size_t begin = text.rfind('\n', end - 1);
    begin = begin == std::string_view::npos ? 0 : begin + 1;
    std::string_view line = text.substr(begin, end - begin);
    if (!line.empty() && line.back() == '\n') line.remove_suffix(1);
    if (line.find_first_not_of(" \t\r") != std::string_view::npos) {
      std::string out;
      for (char c : line) {
        if (out.size() >= max) {
          out += "...";
          break;
        }
        const auto u = static_cast<unsigned char>(c);
        out += (u < 0x20 && c != '\t') || u == 0x7f ? '?' : c;
      }
      return out;
    }
    end = begin == 0 ? 0 : begin - 1;
  }
  return std::string();
}

std::string recorded_line(std::string_view count, std::string_view artifact, std::string_view why,
                          std::string_view log_name, std::string_view log_text) {
  const std::string last = last_log_line(log_text);
  std::string out = "fail  ";
  out += count;
  out += artifact;
  out += " (";
  out += why;
  out += "; recorded as a failed trial): ";
  out += last.empty() ? "see " + std::string(log_name) : last;
  out += '\n';
  return out;
}

Resources slurm_resources(const std::string& text, const std::string& file,
                          const std::vector<std::string>& command) {
  formats::IniPolicy policy;  // '#' and ';' comments, [tool] sections, each key once per section
  policy.sections = true;
  policy.keys = {"cpus", "mem", "time"};
  const formats::IniFile ini = formats::parse_ini(text, file, policy);
  for (const formats::IniEntry& e : ini.entries) {
    if (e.section.empty()) ini.fail(e.line, "'" + e.key + "' before any [section]");
  }
  Resources r;
  r.section = "default";
  for (const auto& word : command) {
    std::string_view name = word;
    while (name.size() > 1 && name.back() == '/') name.remove_suffix(1);
    const auto slash = name.rfind('/');
    if (slash != std::string_view::npos && name.size() > 1) name.remove_prefix(slash + 1);
    if (std::find(ini.sections.begin(), ini.sections.end(), name) != ini.sections.end()) {
      r.section = std::string(name);
      break;
    }
  }
  for (auto [key, value] : {std::pair{"cpus", &r.cpus}, {"mem", &r.mem}, {"time", &r.time}}) {
    const formats::IniEntry* e = ini.find(r.section, key);
    if (e == nullptr) e = ini.find("default", key);
    if (e == nullptr) ini.fail(0, std::string("no '") + key + "' for [" + r.section + "] or [default]");
    *value = e->value;
  }
  return r;
}

std::string hugepage_tunables(const char* current) {
  const std::string cur = current ? current : "";
  if ((":" + cur).find(":glibc.malloc.hugetlb=") != std::string::npos) return cur;
  return (cur.empty() ? std::string() : cur + ":") + "glibc.malloc.hugetlb=1";
}

}  // namespace canopy::stagerun
