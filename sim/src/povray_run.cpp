// Running POV-Ray: the private directory, signal cleanup, staged includes, child processes.
#include "canopy/sim/povray_run.h"

#include <dirent.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <sstream>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/common/parallel.h"
#include "canopy/common/signals.h"

namespace canopy::sim {

using common::Error;

namespace {

// ---------------------------------------------------------------- signal cleanup
// Fixed storage so the handler touches only async-signal-safe memory and calls.
// rangetrace runs at most kRunsPerThread x 256 (--threads' bound) POV-Ray processes at once.
constexpr int kMaxChildren = 1024;
constexpr int kMaxDirs = 8;
constexpr int kMaxPath = 4096;
// A child slot: 0 free, kForking while its thread forks (signals blocked there), else the pid.
constexpr pid_t kForking = -1;
std::atomic<pid_t> g_children[kMaxChildren];
char g_dirs[kMaxDirs][kMaxPath];
std::atomic<bool> g_dir_used[kMaxDirs];
// Set first thing by the handler: no thread starts another POV-Ray after that (run_process).
std::atomic<bool> g_stopping{false};
// The signals common's atomic writer cleans up after (SIGPIPE and SIGXFSZ too: rangetrace dying
// of a closed stderr pipe must not leave its private directory and POV-Ray behind).
constexpr const auto& kSignals = common::kCleanupSignals;
constexpr int kNumSignals = sizeof kSignals / sizeof kSignals[0];
struct sigaction g_previous[kNumSignals];
std::once_flag g_install_once;

// Removes the files of a flat directory, then the directory (getdents64: no malloc).
void remove_dir_signal_safe(const char* path) {
  const int fd = ::open(path, O_RDONLY | O_DIRECTORY);
  if (fd >= 0) {
    alignas(8) char buf[4096];
    for (;;) {
      const long n = ::syscall(SYS_getdents64, fd, buf, sizeof buf);
      if (n <= 0) break;
      for (long off = 0; off < n;) {
        const char* rec = buf + off;
        unsigned short reclen;
        std::memcpy(&reclen, rec + 16, sizeof reclen);
        const char* name = rec + 19;
        if (!(name[0] == '.' && (name[1] == 0 || (name[1] == '.' && name[2] == 0)))) {
          ::unlinkat(fd, name, 0);
        }
        off += reclen;
      }
    }
    ::close(fd);
  }
  ::rmdir(path);
}

// Kills a supervisor (run_process) and its process group. The supervisor itself first: until
// it has called setsid() its group does not exist yet (kill(-pid) fails), and once it is dead
// it starts nothing more; a command it already started is in its group.
void kill_supervisor(pid_t pid) {
  ::kill(pid, SIGKILL);
  ::kill(-pid, SIGKILL);
}

extern "C" void kill_children_and_clean(int sig, siginfo_t* info, void* context) {
  g_stopping.store(true);
  // Each child leads its own process group (run_process): POV-Ray, bwrap and its jail with it.
  // A slot still kForking belongs to a thread between fork and registration: it is a pid soon.
  for (auto& c : g_children) {
    pid_t pid = c.load();
    for (int spins = 0; pid == kForking && spins < 100000; ++spins) {
      const struct timespec pause = {0, 10000};
      ::nanosleep(&pause, nullptr);
      pid = c.load();
    }
    if (pid > 0) kill_supervisor(pid);
  }
  for (auto& c : g_children) {
    const pid_t pid = c.exchange(0);
    if (pid > 0) {
      while (::waitpid(pid, nullptr, 0) < 0 && errno == EINTR) {}
    }
  }
  for (int i = 0; i < kMaxDirs; ++i) {
    if (g_dir_used[i].exchange(false)) remove_dir_signal_safe(g_dirs[i]);
  }
  // Chain to the handler that was there before (common's: removes pending outputs and
  // re-raises), in either style, or die of the signal.
  for (int k = 0; k < kNumSignals; ++k) {
    if (kSignals[k] != sig) continue;
    const auto& prev = g_previous[k];
    if ((prev.sa_flags & SA_SIGINFO) != 0 && prev.sa_sigaction != nullptr) {
      prev.sa_sigaction(sig, info, context);
    } else if ((prev.sa_flags & SA_SIGINFO) == 0 && prev.sa_handler != SIG_DFL &&
               prev.sa_handler != SIG_IGN && prev.sa_handler != nullptr) {
      prev.sa_handler(sig);
    }
  }
  common::reraise_with_default_action(sig);
}

// The supervisor's handler (run_process): kills its process group, itself included.
extern "C" void kill_own_group(int) {
  ::kill(0, SIGKILL);
  ::_exit(137);
}

// A signal ignored when rangetrace starts stays ignored (nohup, a background job of a script:
// SIGINT ignored), as common's handlers do: rangetrace must not die of it.
void install_handlers() {
  for (int k = 0; k < kNumSignals; ++k) {
    struct sigaction old {};
    sigaction(kSignals[k], nullptr, &old);
    if ((old.sa_flags & SA_SIGINFO) == 0 && old.sa_handler == SIG_IGN) continue;
    struct sigaction sa {};
    sa.sa_sigaction = kill_children_and_clean;
    sa.sa_flags = SA_SIGINFO;
    sigemptyset(&sa.sa_mask);
    for (int s : kSignals) sigaddset(&sa.sa_mask, s);
    sigaction(kSignals[k], &sa, &g_previous[k]);
  }
}

void block_signals(sigset_t* old) {
  sigset_t set;
  sigemptyset(&set);
  for (int s : kSignals) sigaddset(&set, s);
  pthread_sigmask(SIG_BLOCK, &set, old);
}

// POV-Ray's own error lines from its console log: from the first line that mentions an error,
// with its 80-column wrapping undone.
std::string povray_message(const std::string& log) {
  std::istringstream in(log);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  std::size_t first = lines.size();
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (lines[i].find("Error") != std::string::npos || lines[i].find("error") != std::string::npos) {
      first = i;
      break;
    }
  }
  if (first == lines.size()) first = lines.size() > 8 ? lines.size() - 8 : 0;
  // A wrapped line continues with a leading space: start at the beginning of the message.
  while (first > 0 && lines[first].rfind(' ', 0) == 0) --first;
  std::string msg;
  for (std::size_t i = first; i < lines.size(); ++i) {
    if (lines[i].find_first_not_of(' ') == std::string::npos) continue;
    if (!msg.empty()) msg += lines[i].rfind(' ', 0) == 0 ? "" : "\n  ";
    msg += lines[i];
  }
  return msg;
}

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  if (from.empty()) return s;
  for (std::size_t pos = 0; (pos = s.find(from, pos)) != std::string::npos; pos += to.size()) {
    s.replace(pos, from.size(), to);
  }
  return s;
}

std::string absolute(const std::string& path) {
  char buf[PATH_MAX];
  if (::realpath(path.c_str(), buf) != nullptr) return buf;
  return path;
}

// Removes the private directories of rangetrace runs that died without cleaning up (SIGKILL,
// power loss): those whose "owner" file names a process that no longer exists. Directories
// of live runs, of other users, and without an owner file are left alone.
void sweep_stale(const std::string& base) {
  DIR* d = ::opendir(base.c_str());
  if (d == nullptr) return;
  std::vector<std::string> stale;
  while (dirent* e = ::readdir(d)) {
    const std::string name = e->d_name;
    if (name.rfind("rangetrace-", 0) != 0) continue;
    const std::string dir = base + "/" + name;
    struct stat st {};
    if (::lstat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode) || st.st_uid != ::getuid()) continue;
    std::string owner;
    try {
      owner = common::read_file(dir + "/owner");
    } catch (const Error&) { continue; }
    const long pid = std::strtol(owner.c_str(), nullptr, 10);
    if (pid > 0 && ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) stale.push_back(dir);
  }
  ::closedir(d);
  for (const auto& dir : stale) {
    remove_dir_signal_safe(dir.c_str());
    common::log::debug("removed the stale " + dir + " of a run that was killed");
  }
}

}  // namespace

// ---------------------------------------------------------------- TempDir

TempDir::TempDir() {
  const char* base = std::getenv("TMPDIR");
  const std::string base_dir = base && *base ? base : "/tmp";
  sweep_stale(base_dir);
  std::string templ = base_dir + "/rangetrace-XXXXXX";
  std::vector<char> buf(templ.begin(), templ.end());
  buf.push_back('\0');
  if (mkdtemp(buf.data()) == nullptr) {
    throw Error("cannot create a temporary directory in " + templ + ": " + std::strerror(errno));
  }
  path_ = buf.data();
  // The owner's pid lets a later run remove the directory if this one is killed (SIGKILL).
  // Writing it also makes common's atomic writer install its signal handlers now, so that
  // ours (installed next) come first and chain to it.
  common::write_file_atomic(path_ + "/owner", std::to_string(::getpid()) + "\n");
  std::call_once(g_install_once, install_handlers);
  if (path_.size() < static_cast<std::size_t>(kMaxPath)) {
    sigset_t old;
    block_signals(&old);
    for (int i = 0; i < kMaxDirs; ++i) {
      if (!g_dir_used[i].load()) {
        std::memcpy(g_dirs[i], path_.c_str(), path_.size() + 1);
        g_dir_used[i].store(true);
        slot_ = i;
        break;
      }
    }
    pthread_sigmask(SIG_SETMASK, &old, nullptr);
  }
}

TempDir::~TempDir() {
  sigset_t old;
  block_signals(&old);
  if (slot_ >= 0) g_dir_used[slot_].store(false);
  for (const auto& f : files()) ::unlink((path_ + "/" + f).c_str());
  ::rmdir(path_.c_str());
  pthread_sigmask(SIG_SETMASK, &old, nullptr);
}

std::vector<std::string> TempDir::files() const {
  std::vector<std::string> out;
  if (DIR* d = ::opendir(path_.c_str())) {
    while (dirent* e = ::readdir(d)) {
      const std::string n = e->d_name;
      if (n != "." && n != "..") out.push_back(n);
    }
    ::closedir(d);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// ---------------------------------------------------------------- staging and running

Staged stage_models(const std::vector<Model>& models, const TempDir& tmp) {
  Staged st;
  for (std::size_t k = 0; k < models.size(); ++k) {
    const Model& m = models[k];
    if (m.include_dir.empty()) {
      st.include_code.push_back(m.inline_code);
      continue;
    }
    const std::string dir = absolute(m.include_dir);
    const std::string file = dir + "/" + m.include_file;
    const std::string link_dir = "inc" + std::to_string(k);
    const std::string link_file = "model" + std::to_string(k) + ".inc";
    ::unlink((tmp.path() + "/" + link_dir).c_str());  // staged before (extents)
    ::unlink((tmp.path() + "/" + link_file).c_str());
    if (::symlink(dir.c_str(), (tmp.path() + "/" + link_dir).c_str()) != 0 ||
        ::symlink(file.c_str(), (tmp.path() + "/" + link_file).c_str()) != 0) {
      throw Error("cannot link '" + file + "' into " + tmp.path() + ": " + std::strerror(errno));
    }
    st.include_code.push_back("#include \"" + link_file + "\"\n");
    st.args.push_back("+L" + link_dir);
    st.renames.emplace_back(link_file, file);
    st.renames.emplace_back(link_dir + "/", dir + "/");
    if (m.user_files.empty()) {
      st.readable.push_back(dir);  // canopy's built-in models
    } else {
      st.user_code = true;
      st.readable.insert(st.readable.end(), m.user_files.begin(), m.user_files.end());
    }
  }
  std::sort(st.readable.begin(), st.readable.end());
  st.readable.erase(std::unique(st.readable.begin(), st.readable.end()), st.readable.end());
  return st;
}

int run_process(const Command& cmd, const std::string& dir, const std::string& log_path) {
  std::vector<std::string> args = cmd.argv, env = cmd.env;
  std::vector<char*> argv, envp;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  for (auto& e : env) envp.push_back(e.data());
  envp.push_back(nullptr);
  // Signals stay blocked from before fork until the child's pid is registered, so the cleanup
  // handler always knows every child; the child restores the mask before exec. The slot is
  // reserved (kForking) before fork: a handler running on another thread meanwhile waits for
  // the pid, and one that ran before finds g_stopping set here, so no POV-Ray starts after it.
  sigset_t old;
  block_signals(&old);
  int slot = -1;
  for (int i = 0; i < kMaxChildren && slot < 0; ++i) {
    pid_t expected = 0;
    if (g_children[i].compare_exchange_strong(expected, kForking)) slot = i;
  }
  if (slot < 0 || g_stopping.load()) {
    if (slot >= 0) g_children[slot].store(0);
    pthread_sigmask(SIG_SETMASK, &old, nullptr);
    throw Error(slot < 0 ? "cannot start POV-Ray: more than " + std::to_string(kMaxChildren) + " at once"
                         : std::string("cannot start POV-Ray: stopping on a signal"));
  }
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int err = errno;
    g_children[slot].store(0);
    pthread_sigmask(SIG_SETMASK, &old, nullptr);
    throw Error(std::string("cannot start POV-Ray: fork: ") + std::strerror(err));
  }
  if (pid == 0) {
    // Child (only async-signal-safe calls): a supervisor leading a new session and process
    // group, without a controlling terminal, that runs the command as its own child and exits
    // with its status. When rangetrace dies, even of SIGKILL, the supervisor gets SIGTERM and
    // kills its whole group: the command and, under bwrap, every process of the jail, whatever
    // stage of its setup bwrap is in (bwrap's own --die-with-parent is armed only once its
    // setup is done: a jail child killed before that would wait for its parent forever).
    ::setsid();
    struct sigaction sa {};
    sa.sa_handler = kill_own_group;
    sigemptyset(&sa.sa_mask);
    for (int s : kSignals) ::sigaction(s, &sa, nullptr);
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (::getppid() != parent) kill_own_group(SIGTERM);
    const int fd = ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    const int null_fd = ::open("/dev/null", O_RDONLY);
    if (fd < 0 || null_fd < 0 || ::chdir(dir.c_str()) != 0) ::_exit(126);
    ::dup2(null_fd, 0);
    ::dup2(fd, 1);
    ::dup2(fd, 2);
    const pid_t supervisor = ::getpid();
    const pid_t command = ::fork();
    if (command < 0) ::_exit(126);
    if (command == 0) {
      for (int s : kSignals) ::signal(s, SIG_DFL);
      ::prctl(PR_SET_PDEATHSIG, SIGKILL);
      if (::getppid() != supervisor) ::_exit(137);  // the supervisor died before the prctl
      pthread_sigmask(SIG_SETMASK, &old, nullptr);
      ::execve(cmd.program.c_str(), argv.data(), envp.data());
      ::_exit(127);
    }
    pthread_sigmask(SIG_SETMASK, &old, nullptr);
    int st = 0;
    while (::waitpid(command, &st, 0) < 0) {
      if (errno != EINTR) ::_exit(126);
    }
    ::_exit(WIFEXITED(st) ? WEXITSTATUS(st) : 128 + (WIFSIGNALED(st) ? WTERMSIG(st) : 0));
  }
  g_children[slot].store(pid);
  pthread_sigmask(SIG_SETMASK, &old, nullptr);
  // Wait without reaping, unregister, then reap: the handler never kills a pid that was reaped
  // (and perhaps reused by another process) while it was still registered.
  siginfo_t info{};
  while (::waitid(P_PID, static_cast<id_t>(pid), &info, WEXITED | WNOWAIT) < 0) {
    if (errno != EINTR) {
      const int err = errno;
      g_children[slot].store(0);
      throw Error(std::string("waitid: ") + std::strerror(err));
    }
  }
  {
    sigset_t held;
    block_signals(&held);
    pid_t expected = pid;
    g_children[slot].compare_exchange_strong(expected, 0);
    pthread_sigmask(SIG_SETMASK, &held, nullptr);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) throw Error(std::string("waitpid: ") + std::strerror(errno));
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return WIFSIGNALED(status) ? 128 + WTERMSIG(status) : 128;
}

void run_povray(const std::string& povray, const Staged& st, const std::string& dir,
                std::vector<std::string> args, const std::string& log_name,
                const std::vector<std::pair<std::string, std::string>>& renames) {
  const std::string log_path = dir + "/" + log_name;
  const Command cmd = povray_command(povray, args, absolute(dir), st.readable, st.user_code);
  // POV-Ray 3.7's front end gives up when its render threads do not start in time (seen at a
  // load of 16 on 2 cores: "Timed out waiting for worker thread startup"), and may then exit 0
  // having parsed nothing. That run did no work: it is run again (at most 3 runs in all).
  int status = 0;
  for (int attempt = 1;; ++attempt) {
    status = run_process(cmd, dir, log_path);
    std::string first;
    try {
      first = common::read_file(log_path);
    } catch (const Error&) {}
    if (attempt >= 3 || first.find("Timed out waiting for worker thread startup") == std::string::npos) break;
    common::log::warn("POV-Ray timed out starting its render threads (machine busy?): run " +
                      std::to_string(attempt + 1) + " of at most 3");
  }
  if (status == 0) return;
  if (status == 127) {
    throw Error("cannot run POV-Ray '" + povray + "' (is the Debian package povray installed?)");
  }
  std::string log;
  try {
    log = common::read_file(log_path);
  } catch (const Error&) {}
  // bwrap's own failure (a path to bind vanished, ...) is a confinement error.
  if (log.rfind("bwrap: ", 0) == 0) {
    throw Error("cannot confine POV-Ray: " + log.substr(0, log.find('\n')));
  }
  std::string msg = povray_message(log);
  for (const auto& [from, to] : renames) msg = replace_all(msg, from, to);
  // An include that leaves a brace open fails only later, in the generated file: say so.
  std::string includes;
  for (const auto& [from, to] : renames) {
    if (from.rfind("model", 0) == 0) includes += (includes.empty() ? "'" : ", '") + to + "'";
  }
  if (!includes.empty() && msg.find("rangetrace's generated") != std::string::npos) {
    msg += "\n  (the error shows after the include: check " + includes +
           " for an unclosed { or ( and that it declares Vehicle)";
  }
  throw Error("POV-Ray failed: " + msg);
}

std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> models_extent(const std::vector<Model>& models,
                                                                       const std::string& povray,
                                                                       const TempDir& tmp) {
  const Staged st = stage_models(models, tmp);
  std::string pov = "#version 3.7;\nglobal_settings { assumed_gamma 1.0 }\n";
  pov += "#fopen ExtentFile \"extent.txt\" write\n";
  for (std::size_t k = 0; k < models.size(); ++k) {
    std::string name = models[k].name;
    for (char& c : name) {
      if (c == '"' || c == '\\' || static_cast<unsigned char>(c) < 32) c = '_';
    }
    pov += "#ifdef (Vehicle) #undef Vehicle #end\n";
    pov += st.include_code[k];
    pov += "#ifndef (Vehicle)\n#error \"the model " + name + " does not declare Vehicle\"\n#end\n";
    pov +=
        "#write (ExtentFile, vstr(3, min_extent(Vehicle), \" \", 0, 9), \" \", "
        "vstr(3, max_extent(Vehicle), \" \", 0, 9), \"\\n\")\n";
  }
  pov += "#fclose ExtentFile\n";
  common::write_file_atomic(tmp.path() + "/extent.pov", pov);
  std::vector<std::string> args = {"-D", "-P", "-V", "+WT1"};
  args.insert(args.end(), st.args.begin(), st.args.end());
  args.insert(args.end(), {"+W1", "+H1", "-F", "+Iextent.pov"});
  auto renames = st.renames;
  renames.emplace_back("extent.pov", "rangetrace's generated extent.pov (after the model's include)");
  run_povray(povray, st, tmp.path(), args, "extent.log", renames);
  std::istringstream in(common::read_file(tmp.path() + "/extent.txt"));
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> out;
  for (const Model& model : models) {
    Eigen::Vector3d lo, hi;
    if (!(in >> lo.x() >> lo.y() >> lo.z() >> hi.x() >> hi.y() >> hi.z())) {
      throw Error("cannot read the model's extent from POV-Ray");
    }
    if (!(lo.array() < hi.array()).all() || lo.cwiseAbs().maxCoeff() > 1e5 || hi.cwiseAbs().maxCoeff() > 1e5) {
      throw Error("model '" + model.name + "': Vehicle is empty, flat or unbounded (extent " +
                  std::to_string(lo.x()) + ".." + std::to_string(hi.x()) + ")");
    }
    // pov_frame is a permutation of axes, so it maps the box corners to the box corners.
    out.emplace_back(pov_frame(lo), pov_frame(hi));
  }
  return out;
}

void warn_model_size(const Model& model, const Eigen::Vector3d& size, const Eigen::Vector3d* crop) {
  char dims[128];
  std::snprintf(dims, sizeof dims, "%.3g x %.3g x %.3g m", size.x(), size.y(), size.z());
  const std::string units = crop ? "--units mm" : "units=mm on its vehicle line";
  if (size.maxCoeff() > 30) {
    common::log::warn("model '" + model.name + "' is " + dims +
                      ", longer than 30 m for a vehicle: did you forget " + units + "?");
  } else if (crop && (size.x() > crop->x() || size.y() > crop->y() || size.z() > crop->z())) {
    char box[96];
    std::snprintf(box, sizeof box, "%.3g x %.3g x %.3g m", crop->x(), crop->y(), crop->z());
    common::log::warn("model '" + model.name + "' is " + dims + ", larger than the crop box (" + box +
                      "; points outside it are dropped): did you forget " + units + " or --crop-*?");
  }
}

std::vector<std::string> window_args(const FrameRange& r) {
  if (r.col0 < 0) return {};
  // [lo, hi] clamped to [0, size - 1] and widened to at least 2 pixels (where the image has 2).
  auto span = [](int lo, int hi, int size) {
    lo = std::clamp(lo, 0, size - 1);
    hi = std::clamp(hi, lo, size - 1);
    if (hi == lo && hi + 1 < size) {
      ++hi;
    } else if (hi == lo && lo > 0) {
      --lo;
    }
    return std::make_pair(lo, hi);
  };
  const auto [c0, c1] = span(r.col0, r.col1, r.width);
  const auto [r0, r1] = span(r.row0, r.row1, r.height);
  if (c0 == 0 && c1 == r.width - 1 && r0 == 0 && r1 == r.height - 1) return {};
  if (c1 == 0 || r1 == 0) return {};  // a 1-pixel image: "+EC1" would be read as a fraction
  return {"+SC" + std::to_string(c0 + 1), "+EC" + std::to_string(c1 + 1), "+SR" + std::to_string(r0 + 1),
          "+ER" + std::to_string(r1 + 1)};
}

std::map<int, std::string> render_frames(const std::string& povray, const TempDir& tmp, const Staged& st,
                                         const std::string& pov, int frames,
                                         const std::vector<FrameRange>& ranges, int processes,
                                         const std::vector<std::pair<std::string, std::string>>& renames) {
  std::atomic<std::size_t> next{0};
  std::vector<std::string> errors(ranges.size());
  const int workers = std::min<int>(processes, static_cast<int>(ranges.size()));
  common::parallel_for(workers, workers, [&](std::size_t, std::size_t) {
    for (std::size_t t; (t = next.fetch_add(1)) < ranges.size();) {
      const FrameRange& r = ranges[t];
      std::vector<std::string> args = {"-D", "-P", "-V", "+WT1"};
      args.insert(args.end(), st.args.begin(), st.args.end());
      args.insert(args.end(), {"+W" + std::to_string(r.width), "+H" + std::to_string(r.height), "-A", "+FP16",
                               "File_Gamma=1.0", "+I" + pov, "+Of.ppm", "+KFI0",
                               "+KFF" + std::to_string(frames - 1), "+KI0", "+KF" + std::to_string(frames - 1),
                               "+SF" + std::to_string(r.first), "+EF" + std::to_string(r.last)});
      const std::vector<std::string> window = window_args(r);
      args.insert(args.end(), window.begin(), window.end());
      try {
        run_povray(povray, st, tmp.path(), args, "render" + std::to_string(t) + ".log", renames);
      } catch (const std::exception& e) { errors[t] = e.what(); }
    }
  });
  for (const auto& e : errors) {
    if (!e.empty()) throw Error(e);
  }
  // Frame files are f<number>.ppm with POV-Ray's zero padding.
  std::map<int, std::string> files;
  for (const auto& f : tmp.files()) {
    if (f.size() > 5 && f[0] == 'f' && f.compare(f.size() - 4, 4, ".ppm") == 0) {
      files[std::atoi(f.substr(1, f.size() - 5).c_str())] = tmp.path() + "/" + f;
    }
  }
  return files;
}

}  // namespace canopy::sim
