// Confining POV-Ray with bubblewrap (layer 1 of docs/decisions/sandbox.md).
#include "canopy/sim/sandbox.h"

#include <limits.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <sstream>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/sim/povray_run.h"

namespace canopy::sim {

using common::Error;

namespace {

// PATH for POV-Ray and the lookup of bare program names (POV-Ray's own environment is this
// PATH and HOME = the private directory, whatever rangetrace's environment holds).
constexpr const char* kPath = "/usr/local/bin:/usr/bin:/bin";

std::string real_path(const std::string& path) {
  char buf[PATH_MAX];
  return ::realpath(path.c_str(), buf) != nullptr ? std::string(buf) : std::string();
}

bool executable(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(path.c_str(), X_OK) == 0;
}

// A program name looked up on `path_list` (or taken as a path when it holds a '/'); "" when
// there is no such executable.
std::string find_program(const std::string& name, const std::string& path_list) {
  if (name.empty()) return "";
  if (name.find('/') != std::string::npos) return executable(name) ? real_path(name) : "";
  std::stringstream dirs(path_list);
  for (std::string dir; std::getline(dirs, dir, ':');) {
    if (dir.empty()) dir = ".";
    const std::string candidate = dir + "/" + name;
    if (executable(candidate)) return real_path(candidate);
  }
  return "";
}

std::string env_or(const char* name, const std::string& fallback) {
  const char* v = std::getenv(name);
  return v != nullptr && *v != '\0' ? std::string(v) : fallback;
}

bool under(const std::string& path, const std::string& dir) {
  return path.size() > dir.size() && path.compare(0, dir.size(), dir) == 0 && path[dir.size()] == '/';
}

// The jail's fixed part: namespaces, no capabilities, the system's programs and libraries
// read-only (the top-level /bin, /lib... as on the host: symbolic links into /usr on a
// merged-/usr Debian), POV-Ray's configuration, a minimal /dev. No --new-session: run_process
// already starts a new session without a controlling terminal (no TIOCSTI), and the jail must
// stay in that process group, which is how it is killed.
std::vector<std::string> jail_base() {
  std::vector<std::string> a = {
      "--unshare-all", "--as-pid-1", "--die-with-parent", "--cap-drop", "ALL", "--ro-bind", "/usr", "/usr"};
  for (const char* top : {"/bin", "/sbin", "/lib", "/lib32", "/lib64", "/libx32"}) {
    struct stat st {};
    if (::lstat(top, &st) != 0) continue;
    if (S_ISLNK(st.st_mode)) {
      char target[PATH_MAX];
      const ssize_t n = ::readlink(top, target, sizeof target - 1);
      if (n <= 0) continue;
      a.insert(a.end(), {"--symlink", std::string(target, static_cast<std::size_t>(n)), top});
    } else if (S_ISDIR(st.st_mode)) {
      a.insert(a.end(), {"--ro-bind", top, top});
    }
  }
  a.insert(a.end(), {"--ro-bind-try", "/etc/ld.so.cache", "/etc/ld.so.cache", "--ro-bind-try", "/etc/povray",
                     "/etc/povray", "--dev", "/dev"});
  return a;
}

// Whether bwrap can build the jail here, checked once per process by running `true` in it.
struct BwrapState {
  std::string program;  // absolute path, "" when not found
  bool usable = false;
  std::string problem;  // why not
};

std::once_flag g_probe_once;
BwrapState g_bwrap;
std::atomic<bool> g_warned{false};

void probe_bwrap(const std::string& workdir) {
  const std::string name = env_or("CANOPY_BWRAP", "bwrap");
  g_bwrap.program = find_program(name, env_or("PATH", kPath));
  if (g_bwrap.program.empty()) {
    g_bwrap.problem = "'" + name + "' not found (install the Debian package bubblewrap)";
    return;
  }
  const std::string truth = find_program("true", "/usr/bin:/bin");
  Command probe{g_bwrap.program, {g_bwrap.program}, {"PATH=" + std::string(kPath), "HOME=" + workdir}};
  for (const auto& a : jail_base()) probe.argv.push_back(a);
  probe.argv.insert(probe.argv.end(), {"--remount-ro", "/", "--", truth.empty() ? "/bin/true" : truth});
  const std::string log = workdir + "/bwrap-probe.log";
  const int status = run_process(probe, workdir, log);
  if (status == 0) {
    g_bwrap.usable = true;
    return;
  }
  std::string said;
  try {
    said = common::read_file(log);
  } catch (const Error&) {}
  ::unlink(log.c_str());
  while (!said.empty() && (said.back() == '\n' || said.back() == ' ')) said.pop_back();
  const auto nl = said.rfind('\n');
  if (nl != std::string::npos) said = said.substr(nl + 1);
  g_bwrap.problem = g_bwrap.program + " cannot create the jail (" +
                    (said.empty() ? "exit status " + std::to_string(status) : said) +
                    "; are unprivileged user namespaces disabled?)";
}

}  // namespace

Command povray_command(const std::string& povray, const std::vector<std::string>& povray_args,
                       const std::string& workdir, const std::vector<std::string>& readable, bool user_code) {
  const SandboxMode mode = sandbox_mode();
  const std::string program = find_program(povray, env_or("PATH", kPath));
  if (program.empty()) {
    throw Error("cannot run POV-Ray '" + povray + "' (is the Debian package povray installed?)");
  }
  Command cmd;
  // HOME: POV-Ray reads no user configuration; POV_TEMP_DIR: its temporary files (a large
  // image is held in one) go to the private directory too, not to /tmp.
  cmd.env = {"PATH=" + std::string(kPath), "HOME=" + workdir, "POV_TEMP_DIR=" + workdir};
  if (mode == SandboxMode::kOff) {
    if (user_code && !g_warned.exchange(true)) {
      common::log::warn(
          "POV-Ray runs unconfined (CANOPY_POVRAY_SANDBOX=off): the user include passed the include check "
          "only (docs/decisions/sandbox.md)");
    }
  } else {
    std::call_once(g_probe_once, probe_bwrap, workdir);
    if (!g_bwrap.usable) {
      if (mode == SandboxMode::kBwrap || user_code) {
        throw Error("cannot confine POV-Ray: " + g_bwrap.problem +
                    (user_code ? "; a user include is only rendered confined" : "") +
                    " (CANOPY_POVRAY_SANDBOX=off runs POV-Ray unconfined, with the include check alone: "
                    "docs/decisions/sandbox.md)");
      }
      if (!g_warned.exchange(true)) {
        common::log::warn(
            "POV-Ray runs unconfined: " + g_bwrap.problem +
            " (only canopy's own models and scenes are rendered; a user include would be refused)");
      }
    } else {
      cmd.program = g_bwrap.program;
      cmd.argv = {g_bwrap.program};
      for (const auto& a : jail_base()) cmd.argv.push_back(a);
      if (!under(program, "/usr")) cmd.argv.insert(cmd.argv.end(), {"--ro-bind", program, program});
      for (const auto& r : readable) cmd.argv.insert(cmd.argv.end(), {"--ro-bind", r, r});
      cmd.argv.insert(cmd.argv.end(),
                      {"--bind", workdir, workdir, "--remount-ro", "/", "--chdir", workdir, "--"});
      cmd.argv.push_back(program);
      cmd.argv.insert(cmd.argv.end(), povray_args.begin(), povray_args.end());
      return cmd;
    }
  }
  cmd.program = program;
  cmd.argv = {povray};
  cmd.argv.insert(cmd.argv.end(), povray_args.begin(), povray_args.end());
  return cmd;
}

}  // namespace canopy::sim
