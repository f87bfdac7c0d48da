// stagerun [--launch local|slurm] [--record-failure] ARTIFACT -- COMMAND...: runs one experiment
// stage for make, in one process around the tool (stagerun.h; docs/decisions/cost.md §19):
// fork/exec of COMMAND with its stderr in ARTIFACT.log, wait4() for its CPU and peak memory,
// ARTIFACT.time in GNU time's "%e %M %U %S" format, the progress count under flock(2), one
// "done" or "FAIL" line.
//
// --launch slurm: the command runs as a Slurm job through srun, with the CPUs, memory and time
// limit of its tool's section in share/resources.ini (CANOPY_RESOURCES; the first word of
// COMMAND whose name has a section there; else [default]). CANOPY_SRUN_FLAGS adds site options
// (partition, account). The job runs `stagerun --measure ARTIFACT.time -- COMMAND...` (this
// binary, by its own path, on the filesystem shared by all nodes), which writes ARTIFACT.time
// there as GNU time -o would; ARTIFACT.log is srun's stderr, the job's included. srun passes the
// exit status on, and Ctrl-C (SIGINT to make's process group) makes srun cancel the job at once
// (--quit-on-interrupt).
//
// --record-failure: for ablation variants, where a stage failing is a result (e.g. the thesis's
// fixed RMS bound keeps no voxel at 32 mm): when the tool itself exits with a status from 1 to
// 125 (its own error; canopy's tools exit 1 or 2), the failure is logged, ARTIFACT is created
// empty as an explicit "failed" marker, the status is 0, and the stage's line is one lower-case
// "fail  N/M ARTIFACT (exit S; recorded as a failed trial): <the log's last line>" (not make's
// "FAIL" with the log's tail: an expected outcome, e.g. a too-sparse tile candidate's fitvox,
// that collect turns into a reason). Later stages fail on the empty
// input in turn, so the trial's match.json is empty and counts as not recognised. A tool killed
// by a signal (Ctrl-C, SIGTERM, the OOM killer's SIGKILL, a Slurm time limit), a status of 126
// or more (could not execute, not found, a signal passed on by a wrapper), or a launch that
// never ran the tool (srun could not get an allocation) is never a result: it fails make and
// leaves no ARTIFACT. The .time's first line ("Command terminated by signal 9") tells the cases
// apart.
//
// Large blocks in transparent huge pages (glibc >= 2.35 madvises its heap and mmap'd blocks):
// a tile's scan of millions of points then spends far less in page faults and TLB misses (detect
// on a 2.5 M point tile: 4.8 -> 2.6 CPU-s); outputs do not change (cost.md §15). The command
// gets GLIBC_TUNABLES with glibc.malloc.hugetlb=1; CANOPY_HUGEPAGES=0 (make HUGEPAGES=0) leaves
// glibc's default; the user's own GLIBC_TUNABLES are kept, and one of theirs naming hugetlb wins.
//
// A time box or Ctrl-C (SIGTERM, SIGINT) during the run: the signal is passed on to the command
// (it has it already when it went to the process group), and once the command has ended,
// ARTIFACT.time is removed, the stage is not counted, and stagerun ends by the same signal, as
// make expects. From the command's end on, SIGTERM and SIGINT are held back: a time box or
// Ctrl-C that stops make then leaves the stage either counted (its artifact in
// $CANOPY_PROGRESS-counted) or, stopped before, uncounted and without its .time, which is how
// progress.sh drop tells the two apart (mk/real.mk), and never half-written progress state.
#include <fcntl.h>
#include <sys/file.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <exception>
#include <string>
#include <vector>

#include "stagerun/stagerun.h"

namespace sr = canopy::stagerun;

namespace {

constexpr const char* kUsage =
    "usage: stagerun [--launch local|slurm] [--record-failure] ARTIFACT -- COMMAND...\n"
    "       stagerun --measure TIMEFILE -- COMMAND...\n"
    "Runs one experiment stage: COMMAND's stderr to ARTIFACT.log, its wall time, peak memory and\n"
    "CPU to ARTIFACT.time (GNU time's \"%e %M %U %S\"), one \"done\", \"FAIL\" or \"fail\" line with\n"
    "the progress count of $CANOPY_PROGRESS (Makefile.experiments; docs/decisions/cost.md §19).\n"
    "  --launch local|slurm  run COMMAND here (default) or as a Slurm job (srun, with the\n"
    "                        resources of its tool in $CANOPY_RESOURCES)\n"
    "  --record-failure      the tool's own failure (exit 1-125) is a result: an empty ARTIFACT, status 0,\n"
    "                        one \"fail\" line with the log's last line (not \"FAIL\", which stops make)\n"
    "  --measure TIMEFILE    only run COMMAND and write TIMEFILE as GNU time -o does (the Slurm job)\n"
    "  --help, --version\n";

// The signals stagerun handles or ignores itself, and their dispositions as inherited (what the
// command gets).
constexpr int kOwnSignals[3] = {SIGTERM, SIGINT, SIGQUIT};
struct sigaction g_inherited[3];

volatile sig_atomic_t g_stop = 0;   // SIGTERM or SIGINT received
volatile sig_atomic_t g_child = 0;  // the command's pid while it runs

void on_stop(int sig) {
  if (g_stop == 0) g_stop = sig;
  const pid_t child = g_child;
  if (child > 0) kill(child, sig);
}

[[noreturn]] void usage_error(const std::string& message) {
  std::fprintf(stderr, "stagerun: error: %s\n%s", message.c_str(), kUsage);
  std::exit(2);
}

[[noreturn]] void fail(const std::string& message) {
  std::fprintf(stderr, "stagerun: error: %s\n", message.c_str());
  std::exit(1);
}

bool write_all(int fd, const std::string& text) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

// The file's text (its last MAX bytes when it is longer); "" when it cannot be read.
std::string read_text(const std::string& path, off_t max = 1 << 20) {
  const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return std::string();
  std::string text;
  struct stat st;
  if (fstat(fd, &st) == 0 && st.st_size > max) lseek(fd, st.st_size - max, SEEK_SET);
  char buf[8192];
  for (;;) {
    const ssize_t n = read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    text.append(buf, static_cast<std::size_t>(n));
  }
  close(fd);
  return text;
}

bool append_line(const std::string& path, const std::string& line) {
  const int fd = open(path.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0666);
  if (fd < 0) return false;
  const bool ok = write_all(fd, line);
  close(fd);
  return ok;
}

// mkdir -p DIR
void make_dirs(const std::string& dir) {
  struct stat st;
  if (dir.empty() || stat(dir.c_str(), &st) == 0) return;
  const auto slash = dir.find_last_of('/');
  if (slash != std::string::npos && slash > 0) make_dirs(dir.substr(0, slash));
  if (mkdir(dir.c_str(), 0777) != 0 && errno != EEXIST) {
    fail("cannot create the directory '" + dir + "': " + std::strerror(errno));
  }
}

std::int64_t micros(const timespec& t) {
  return static_cast<std::int64_t>(t.tv_sec) * 1000000 + t.tv_nsec / 1000;
}
std::int64_t micros(const timeval& t) { return static_cast<std::int64_t>(t.tv_sec) * 1000000 + t.tv_usec; }

// Runs COMMAND (its stderr to STDERR_FD unless -1) and waits for it: its wait status, wall clock
// and rusage as wait4() gives them. SIGTERM and SIGINT, when caught (on_stop), are passed on to
// it, and are held back from its end on. A command that cannot be executed exits 127 (not found) or
// 126, its reason on its stderr, as GNU time does.
sr::Usage launch(const std::vector<std::string>& command, int stderr_fd) {
  std::vector<char*> argv;
  for (const auto& w : command) argv.push_back(const_cast<char*>(w.c_str()));
  argv.push_back(nullptr);
  sigset_t stop, before;
  sigemptyset(&stop);
  sigaddset(&stop, SIGTERM);
  sigaddset(&stop, SIGINT);
  sigprocmask(SIG_BLOCK, &stop, &before);
  sr::Usage usage;
  if (g_stop != 0) return usage;
  timespec start, end;
  clock_gettime(CLOCK_MONOTONIC, &start);
  const pid_t pid = fork();
  if (pid == 0) {
    for (int k = 0; k < 3; ++k) sigaction(kOwnSignals[k], &g_inherited[k], nullptr);
    sigprocmask(SIG_SETMASK, &before, nullptr);
    if (stderr_fd >= 0 && stderr_fd != STDERR_FILENO) dup2(stderr_fd, STDERR_FILENO);
    execvp(argv[0], argv.data());
    const int err = errno;
    const std::string message = "stagerun: cannot run " + command.front() + ": " + std::strerror(err) + "\n";
    write_all(STDERR_FILENO, message);
    _exit(err == ENOENT ? 127 : 126);
  }
  if (pid < 0) {
    const std::string message = std::string("stagerun: cannot fork: ") + std::strerror(errno) + "\n";
    if (stderr_fd >= 0) write_all(stderr_fd, message);
    usage.wait_status = 126 << 8;
    return usage;
  }
  g_child = pid;
  sigprocmask(SIG_SETMASK, &before, nullptr);
  // (waitid with WNOWAIT: the command has ended but is not reaped, so its pid is not reused
  // while a signal may still be passed on to it; then the signals are held back and it is reaped)
  siginfo_t info;
  while (waitid(P_PID, pid, &info, WEXITED | WNOWAIT) != 0 && errno == EINTR) {}
  clock_gettime(CLOCK_MONOTONIC, &end);
  sigprocmask(SIG_BLOCK, &stop, nullptr);
  g_child = 0;
  rusage ru{};
  int status = 0;
  while (wait4(pid, &status, 0, &ru) < 0 && errno == EINTR) {}
  usage.wait_status = status;
  usage.wall_us = micros(end) - micros(start);
  usage.user_us = micros(ru.ru_utime);
  usage.sys_us = micros(ru.ru_stime);
  usage.max_rss_kib = ru.ru_maxrss;
  return usage;
}

// stagerun --measure TIMEFILE -- COMMAND...: GNU time -o TIMEFILE -f "%e %M %U %S" COMMAND (the
// Slurm job's side). SIGINT and SIGQUIT are ignored while the command runs, as GNU time does.
int measure(const std::string& file, const std::vector<std::string>& command) {
  const int fd = open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) fail(file + ": cannot write the time file: " + std::strerror(errno));
  struct sigaction ign {};
  ign.sa_handler = SIG_IGN;
  sigaction(SIGINT, &ign, nullptr);
  sigaction(SIGQUIT, &ign, nullptr);
  const sr::Usage usage = launch(command, -1);
  write_all(fd, sr::time_file_text(usage));
  close(fd);
  return sr::time_exit_status(usage.wait_status);
}

bool on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "/usr/bin:/bin";
  std::size_t at = 0;
  while (at <= dirs.size()) {
    std::size_t colon = dirs.find(':', at);
    if (colon == std::string::npos) colon = dirs.size();
    std::string dir = dirs.substr(at, colon - at);
    if (dir.empty()) dir = ".";
    if (access((dir + "/" + name).c_str(), X_OK) == 0) return true;
    at = colon + 1;
  }
  return false;
}

// The srun words around COMMAND (--launch slurm).
std::vector<std::string> slurm_command(const std::string& timing, const std::vector<std::string>& command) {
  const char* env = std::getenv("CANOPY_RESOURCES");
  const std::string resources = env && *env ? env : CANOPY_SHARE_DIR "/resources.ini";
  if (access(resources.c_str(), R_OK) != 0) fail(resources + ": cannot read the resources file");
  sr::Resources r;
  try {
    r = sr::slurm_resources(read_text(resources), resources, command);
  } catch (const std::exception& e) { fail(e.what()); }
  const std::string& section = r.section;
  if (!on_path("srun")) fail("srun not found (Debian package slurm-client)");
  const std::vector<std::string> values = {r.cpus, r.mem, r.time};
  char self[4096];
  const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
  if (n <= 0) fail(std::string("cannot find this program's own path: ") + std::strerror(errno));
  self[n] = '\0';
  std::vector<std::string> run = {"srun",
                                  "--quiet",
                                  "--quit-on-interrupt",
                                  "--input=none",
                                  "--job-name=canopy-" + section,
                                  "--nodes=1",
                                  "--ntasks=1",
                                  "--cpus-per-task=" + values[0],
                                  "--mem=" + values[1],
                                  "--time=" + values[2]};
  // site flags are words, split on blanks
  const char* flags = std::getenv("CANOPY_SRUN_FLAGS");
  for (const auto& w : sr::read_fields(flags ? flags : "", 1 << 12)) {
    if (!w.empty()) run.push_back(w);
  }
  run.insert(run.end(), {std::string(self), "--measure", timing, "--"});
  run.insert(run.end(), command.begin(), command.end());
  return run;
}

// The progress count for one finished stage (the state is read and rewritten only under the lock:
// another stage rewrites it in place). Returns N/M and the time left, or nothing without a state.
sr::ProgressStep count_stage(const std::string& artifact, const std::string& kind, const std::string& previous) {
  const char* state = std::getenv("CANOPY_PROGRESS");
  if (state == nullptr || *state == '\0') return {};
  const std::string path = state;
  if (access(path.c_str(), F_OK) != 0) return {};
  const int lock = open((path + ".lock").c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0666);
  if (lock < 0) return {};
  while (flock(lock, LOCK_EX) != 0) {
    if (errno != EINTR) {
      close(lock);
      return {};
    }
  }
  const std::string est = sr::is_wall_seconds(previous) ? std::string() : read_text(path + "-est");
  timespec now;
  clock_gettime(CLOCK_REALTIME, &now);
  const std::int64_t now_ms = static_cast<std::int64_t>(now.tv_sec) * 1000 + now.tv_nsec / 1000000;
  sr::ProgressStep step = sr::progress_step(read_text(path), est, previous, kind, now_ms);
  if (step.valid) {
    // (the stages counted so far, one artifact a line: progress.sh drop finds the stages of a
    // stopped sub-make that ran and were counted)
    append_line(path + "-counted", artifact + "\n");
    const int fd = open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (fd >= 0) {
      write_all(fd, step.state_line);
      close(fd);
    }
  }
  close(lock);
  return step;
}

struct Options {
  std::string launch = "local";
  bool record = false;
  std::string artifact;
  std::vector<std::string> command;
};

Options parse(int argc, char** argv) {
  Options o;
  int i = 1;
  for (; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help") {
      std::fputs(kUsage, stdout);
      std::exit(0);
    } else if (a == "--version") {
      std::puts("stagerun (canopy) " CANOPY_VERSION);
      std::exit(0);
    } else if (a == "--launch") {
      if (i + 1 >= argc) usage_error("--launch needs a value (local or slurm)");
      o.launch = argv[++i];
      if (o.launch != "local" && o.launch != "slurm")
        usage_error("unknown --launch '" + o.launch + "' (local or slurm)");
    } else if (a == "--record-failure") {
      o.record = true;
    } else if (a == "--measure") {
      if (i + 1 >= argc) usage_error("--measure needs a time file");
      const std::string file = argv[++i];
      if (i + 1 < argc && std::string(argv[i + 1]) == "--") ++i;
      if (i + 1 >= argc) usage_error("--measure " + file + ": no command given");
      std::exit(measure(file, std::vector<std::string>(argv + i + 1, argv + argc)));
    } else if (!a.empty() && a[0] == '-') {
      usage_error("unknown option '" + a + "'");
    } else {
      break;
    }
  }
  if (i >= argc) usage_error("no ARTIFACT given");
  o.artifact = argv[i++];
  if (i < argc && std::string(argv[i]) == "--") ++i;
  if (i >= argc) usage_error(o.artifact + ": no command given");
  o.command.assign(argv + i, argv + argc);
  return o;
}

// Ends the process by SIG (SIGTERM or SIGINT, held back until now) with its default action.
[[noreturn]] void die_by(int sig) {
  struct sigaction dfl {};
  dfl.sa_handler = SIG_DFL;
  sigaction(sig, &dfl, nullptr);
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, sig);
  kill(getpid(), sig);
  sigprocmask(SIG_UNBLOCK, &set, nullptr);
  _exit(128 + sig);
}

}  // namespace

int main(int argc, char** argv) {
  for (int k = 0; k < 3; ++k) sigaction(kOwnSignals[k], nullptr, &g_inherited[k]);
  const Options o = parse(argc, argv);
  const std::string& artifact = o.artifact;
  const std::string log = artifact + ".log";
  const std::string timing = artifact + ".time";
  const auto slash = artifact.find_last_of('/');
  if (slash != std::string::npos && slash > 0) make_dirs(artifact.substr(0, slash));

  std::vector<std::string> run = o.command;
  if (o.launch == "slurm") run = slurm_command(timing, o.command);
  const char* hugepages = std::getenv("CANOPY_HUGEPAGES");
  if (hugepages == nullptr || std::string(hugepages) != "0") {
    const char* tunables = std::getenv("GLIBC_TUNABLES");
    const std::string t = sr::hugepage_tunables(tunables);
    if (tunables == nullptr || t != tunables) setenv("GLIBC_TUNABLES", t.c_str(), 1);
  }

  // The kind of this stage and its artifact's previous wall time (this stage's progress
  // estimate), read before the .time is emptied.
  const std::string kind = sr::stage_kind(artifact, o.command);
  const std::string previous = sr::read_fields(sr::first_line(read_text(timing, 4096)), 2)[0];

  struct sigaction catcher {};
  catcher.sa_handler = on_stop;
  sigemptyset(&catcher.sa_mask);
  for (int sig : {SIGTERM, SIGINT}) {
    struct sigaction was;
    sigaction(sig, nullptr, &was);
    if (was.sa_handler != SIG_IGN) sigaction(sig, &catcher, nullptr);  // (ignored by make: stays so)
  }
  // (emptied first, so a launch that never ran the command is told apart from the previous
  // run's times; a stage that does not finish removes it)
  const int time_fd = open(timing.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (time_fd < 0) fail(timing + ": " + std::strerror(errno));
  const int log_fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (log_fd < 0) {
    unlink(timing.c_str());
    fail(log + ": " + std::strerror(errno));
  }
  const sr::Usage usage = launch(run, log_fd);
  close(log_fd);
  int rc = sr::time_exit_status(usage.wait_status);
  std::string time_text;
  if (o.launch == "local" && g_stop == 0) {
    time_text = sr::time_file_text(usage);
    if (!write_all(time_fd, time_text)) time_text.clear();
  }
  close(time_fd);
  if (g_stop != 0) {
    unlink(timing.c_str());
    die_by(g_stop);
  }
  if (o.launch != "local") time_text = read_text(timing, 4096);
  // The .time's first line says how the command ended when it did not exit 0.
  const std::string how = sr::read_fields(sr::first_line(time_text), 1)[0];
  const char* progress = std::getenv("CANOPY_PROGRESS");
  if (rc == 0 && !how.empty() && how.compare(0, 7, "Command") != 0) {
    if (progress && *progress) {
      const auto f = sr::read_fields(how, 2);
      append_line(std::string(progress) + "-history", kind + " " + f[0] + " " + sr::cpu_seconds(how) + "\n");
    }
    const sr::ProgressStep step = count_stage(artifact, kind, previous);
    std::fputs(sr::done_line(step.count, artifact, how, step.left).c_str(), stdout);
    return 0;
  }
  unlink(timing.c_str());
  if (rc == 0) rc = 1;
  bool tool_failed = false;
  const std::string why = sr::failure_words(how, rc, &tool_failed);
  const sr::ProgressStep step = count_stage(artifact, kind, previous);
  if (o.record && tool_failed) {
    // A result: one lower-case line, never make's FAIL (the empty ARTIFACT is the marker).
    const int fd = open(artifact.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (fd < 0) {
      std::printf("FAIL  %s%-58s (%s); last lines of %s:\n", step.count.c_str(), artifact.c_str(),
                  why.c_str(), log.c_str());
      std::fputs(sr::indented_tail(read_text(log, 65536), 5).c_str(), stdout);
      std::fflush(stdout);
      fail(artifact + ": cannot record the failed trial: " + std::strerror(errno));
    }
    close(fd);
    std::fputs(sr::recorded_line(step.count, artifact, why, log, read_text(log, 65536)).c_str(), stdout);
    return 0;
  }
  std::printf("FAIL  %s%-58s (%s); last lines of %s:\n", step.count.c_str(), artifact.c_str(), why.c_str(),
              log.c_str());
  std::fputs(sr::indented_tail(read_text(log, 65536), 5).c_str(), stdout);
  if (o.record) std::puts("      not recorded as a failed trial: the tool did not exit by itself");
  return rc;
}
