// stagerun: the runner of every experiment stage (Makefile.experiments' $(STAGE), mk/*.mk),
// one process around the tool (docs/decisions/cost.md §19; it replaced scripts/stage.sh, whose
// bash, GNU time and flock cost ≈ 28-39 ms of CPU a stage on the experiment machine).
//
//   stagerun [--launch local|slurm] [--record-failure] ARTIFACT -- COMMAND...
//
// The tool's stderr (its INFO lines, warnings, errors) goes to ARTIFACT.log; wall seconds, peak
// memory (KiB), user and system CPU seconds to ARTIFACT.time in GNU time's "%e %M %U %S" format
// (two decimals; preceded by GNU time's "Command exited with non-zero status N" or "Command
// terminated by signal N" line when the command did not exit 0), read by the report through
// documents/stage_time.h. One progress line is printed, "done  N/M ARTIFACT ..." where M is the
// number of stages make planned and N counts the stages finished so far in this make run
// (scripts/progress.sh keeps the state, CANOPY_PROGRESS; updated here under flock(2) on
// CANOPY_PROGRESS.lock). On failure the log's last lines are shown and the status is passed on
// (the tool itself never leaves a partial ARTIFACT). A command that cannot be run exits 127 (not
// found) or 126 (not executable), as GNU time does.
//
// This header holds the rules as functions without processes or locks (tests/stagerun): the
// .time format, the progress state's arithmetic, the kind of a stage, the failure's wording,
// share/resources.ini's lookup. main.cpp runs the command, takes the lock and writes the files.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace canopy::stagerun {

// The `ms` rule of the progress state: TEXT (seconds: digits with an optional fraction, at least
// one digit) in whole milliseconds, further decimals dropped. False when TEXT is no such number.
bool parse_ms(std::string_view text, std::int64_t* ms);

// Whitespace-separated fields of a line as bash's `read -r a b c` splits them: at most `count`
// fields, the last holding the rest of the line (trimmed); missing fields are empty.
std::vector<std::string> read_fields(std::string_view line, int count);

// The first line of TEXT (without its newline).
std::string_view first_line(std::string_view text);

// The kind of a stage, "<tool>:<artifact name, each digit as #>" with "cand/" before the name of
// a candidate's stage (an artifact under /cands/); the tool is the first command word containing
// "/bin/", else the first word (scripts/progress.sh computes the same kind in awk).
std::string stage_kind(std::string_view artifact, const std::vector<std::string>& command);

// What wait4() reported about the command, as GNU time formats it.
struct Usage {
  std::int64_t wall_us = 0;  // elapsed wall clock, microseconds
  std::int64_t user_us = 0;  // user CPU of the command and its waited-for descendants
  std::int64_t sys_us = 0;   // system CPU, same
  long max_rss_kib = 0;      // ru_maxrss (KiB on Linux)
  int wait_status = 0;       // wait4's status
};
// The .time file's text: GNU time's status line when the command did not exit 0, then
// "%e %M %U %S" (seconds with two decimals, truncated, as GNU time 1.9 prints them).
std::string time_file_text(const Usage& usage);
// The exit status GNU time gives for the command's wait status: its exit status, or 128 + the
// signal that ended (or stopped) it.
int time_exit_status(int wait_status);

// The progress state's step for one finished stage. STATE is the state file's text ("N M D E T0
// ..."), EST the estimates' text ("<kind or tool or *> <seconds>" lines), PREVIOUS the first word
// of the artifact's .time before this run, KIND this stage's kind, NOW_MS the clock (Unix ms).
struct ProgressStep {
  bool valid = false;      // false: STATE is no state; nothing is written or shown
  std::string state_line;  // the new state, with its newline
  std::string count;       // "N/M "
  std::string left;        // "  ~T left" or ""
};
// Whether PREVIOUS (the first word of the artifact's earlier .time) is a wall time to estimate
// the stage by ("D" or "D.DDD..."); when it is not, the estimates (EST) are read.
bool is_wall_seconds(std::string_view previous);
ProgressStep progress_step(std::string_view state, std::string_view est, std::string_view previous,
                           std::string_view kind, std::int64_t now_ms);
// "~T s left", "~T min left" or "~H h MM min left" for LEFT_MS milliseconds.
std::string left_text(std::int64_t left_ms);

// The words of a failure: "exit 1", "exit 127, the command could not run", "exit 137, a
// signal", "terminated by signal 9", "exit 1; the tool did not finish". HOW is the .time's first
// line (empty if there is none), RC the status the command or launcher gave. TOOL_FAILED is set
// when the tool itself exited 1-125 (its own error: a result under --record-failure).
std::string failure_words(std::string_view how, int rc, bool* tool_failed);

// The user + system seconds of a .time line ("wall KiB user sys"), "%d.%02d" (0.00 when user or
// system is not "D.CC"), as the history records it and the "done" line shows it.
std::string cpu_seconds(std::string_view time_line);
// The "done" line (with its newline) from the .time's first line: wall s, CPU, MB.
std::string done_line(std::string_view count, std::string_view artifact, std::string_view time_line,
                      std::string_view left);

// The last COUNT lines of TEXT (as tail -n COUNT), each prefixed with six blanks and ended by a
// newline.
std::string indented_tail(std::string_view text, int count);

// The last line of TEXT that is not blank, control bytes as '?', cut to MAX bytes (with "..."
// when cut); "" when there is none. The one line a recorded failure shows of its log.
std::string last_log_line(std::string_view text, std::size_t max = 200);

// The line of a failure recorded as a result (--record-failure; with its newline): "fail  ",
// the progress count, ARTIFACT, "(WHY; recorded as a failed trial)" and the log's last line
// (last_log_line), or "see LOG" when the log has none. Lower case, one line: an expected outcome
// the later stages and collect read, never the "FAIL" that stops make.
std::string recorded_line(std::string_view count, std::string_view artifact, std::string_view why,
                          std::string_view log_name, std::string_view log_text);

// share/resources.ini (formats/ini.h, docs/decisions/ini.md): the Slurm resources of COMMAND.
// Its section is the first command word whose base name is a [section] of the file, else
// [default]; each of cpus, mem, time from that section, else from [default]. DataError naming
// the file (and the line) on a malformed file, an unknown key or a key found in neither.
struct Resources {
  std::string section, cpus, mem, time;
};
Resources slurm_resources(const std::string& text, const std::string& file,
                          const std::vector<std::string>& command);

// GLIBC_TUNABLES for the command: glibc's transparent huge pages added (glibc.malloc.hugetlb=1)
// to CURRENT (null: unset), unless CURRENT already names hugetlb. Returns CURRENT unchanged then.
std::string hugepage_tunables(const char* current);

}  // namespace canopy::stagerun
