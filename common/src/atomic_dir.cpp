#include "canopy/common/atomic_dir.h"

#include <dirent.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <utility>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/common/signals.h"
#include "write_all.h"

namespace canopy::common {
namespace {

namespace fs = std::filesystem;

std::string errno_text(int e) { return std::strerror(e); }

// ---------------------------------------------------------------------------------------
// Signals: the temporary directory is removed on SIGINT, SIGTERM, SIGHUP, SIGPIPE, SIGXFSZ.

constexpr const auto& kSignals = kCleanupSignals;
constexpr int kNumSignals = sizeof kSignals / sizeof kSignals[0];
char g_temp_dir[PATH_MAX];
volatile sig_atomic_t g_temp_set = 0;
volatile sig_atomic_t g_in_handler = 0;
struct sigaction g_previous[kNumSignals];
bool g_installed[kNumSignals];

// Unlinks every entry of a flat directory, then the directory. Async-signal-safe (getdents64,
// unlinkat, rmdir); entries are re-read until none is left, since unlinking while reading may
// skip some.
void remove_flat_dir(const char* path) noexcept {
  const int fd = ::open(path, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return;
  alignas(8) char buf[8192];
  for (int pass = 0; pass < 64; ++pass) {
    bool removed = false;
    ::lseek(fd, 0, SEEK_SET);
    for (;;) {
      const ssize_t n = ::getdents64(fd, buf, sizeof buf);
      if (n <= 0) break;
      for (ssize_t off = 0; off < n;) {
        const auto* d = reinterpret_cast<const struct dirent64*>(buf + off);
        off += d->d_reclen;
        const char* name = d->d_name;
        if (name[0] == '.' && (name[1] == 0 || (name[1] == '.' && name[2] == 0))) continue;
        if (::unlinkat(fd, name, 0) == 0) removed = true;
      }
    }
    if (!removed) break;
  }
  ::close(fd);
  ::rmdir(path);
}

extern "C" void remove_temp_and_reraise(int sig, siginfo_t* info, void* context) {
  if (g_temp_set) remove_flat_dir(g_temp_dir);
  g_temp_set = 0;
  const bool chain = g_in_handler == 0;
  g_in_handler = 1;
  for (int k = 0; chain && k < kNumSignals; ++k) {
    if (kSignals[k] != sig || !g_installed[k]) continue;
    const struct sigaction& prev = g_previous[k];
    if ((prev.sa_flags & SA_SIGINFO) != 0 && prev.sa_sigaction != nullptr) {
      prev.sa_sigaction(sig, info, context);
      return;
    }
    if (prev.sa_handler != SIG_DFL && prev.sa_handler != SIG_IGN && prev.sa_handler != nullptr) {
      prev.sa_handler(sig);
      return;
    }
  }
  reraise_with_default_action(sig);
}

// While armed, the signals above remove `dir` (flat) before taking their previous action. A
// signal ignored when it is armed stays ignored.
void arm_signals(const fs::path& dir) {
  const std::string s = dir.string();
  if (s.size() >= sizeof g_temp_dir) return;
  std::memcpy(g_temp_dir, s.c_str(), s.size() + 1);
  g_in_handler = 0;
  g_temp_set = 1;
  for (int k = 0; k < kNumSignals; ++k) {
    struct sigaction old {};
    sigaction(kSignals[k], nullptr, &old);
    g_installed[k] = false;
    if ((old.sa_flags & SA_SIGINFO) == 0 && old.sa_handler == SIG_IGN) continue;
    g_previous[k] = old;
    struct sigaction sa {};
    sa.sa_sigaction = remove_temp_and_reraise;
    sa.sa_flags = SA_SIGINFO;
    sigemptyset(&sa.sa_mask);
    sigaction(kSignals[k], &sa, nullptr);
    g_installed[k] = true;
  }
}

// The previous actions back.
void disarm_signals() {
  g_temp_set = 0;
  for (int k = 0; k < kNumSignals; ++k) {
    if (g_installed[k]) sigaction(kSignals[k], &g_previous[k], nullptr);
    g_installed[k] = false;
  }
}

// A directory fd, flock'ed exclusively; -1 when another process holds it (or the directory
// cannot be opened).
int lock_dir(const fs::path& dir, bool wait) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return -1;
  if (::flock(fd, LOCK_EX | (wait ? 0 : LOCK_NB)) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

}  // namespace

AtomicDir::AtomicDir(const fs::path& parent, const std::string& name, std::string shown, std::string via,
                     Options options)
    : parent_(parent),
      path_(parent / name),
      temp_(parent / ("." + name + ".tmp" + std::to_string(::getpid()))),
      name_(name),
      shown_(std::move(shown)),
      via_(std::move(via)),
      options_(std::move(options)) {
  if (::mkdir(temp_.c_str(), 0777) != 0) {
    throw DataError(temp_.string(), "cannot create a temporary directory: " + errno_text(errno));
  }
  arm_signals(temp_);
  fd_ = lock_dir(temp_, true);
  if (fd_ < 0) {
    disarm_signals();
    remove_flat_dir(temp_.c_str());
    throw DataError(temp_.string(), "cannot lock the temporary directory");
  }
}

AtomicDir::~AtomicDir() {
  if (fd_ >= 0) ::close(fd_);
  disarm_signals();
  if (!published_) remove_flat_dir(temp_.c_str());
}

void AtomicDir::write(const std::string& name, const std::string& bytes) {
  write_pieces(name, [&bytes](const Sink& sink) { sink(bytes.data(), bytes.size()); });
}

void AtomicDir::write_pieces(const std::string& name, const std::function<void(const Sink&)>& produce) {
  const int fd = ::openat(fd_, name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) throw DataError((temp_ / name).string(), "cannot create: " + errno_text(errno));
  auto failed = [&](int err) {
    return DataError(temp_.string() + "/" + name, "write failed: " + errno_text(err));
  };
  try {
    produce([&](const char* data, std::size_t size) {
      if (const int err = detail::write_all(fd, data, size); err != 0) throw failed(err);
    });
  } catch (...) {
    ::close(fd);
    throw;
  }
  if (::close(fd) != 0) throw failed(errno);
}

void AtomicDir::remove(const std::string& name) {
  if (::unlinkat(fd_, name.c_str(), 0) != 0) {
    throw DataError((temp_ / name).string(), "cannot remove: " + errno_text(errno));
  }
}

void AtomicDir::publish(const std::function<bool()>& check,
                        const std::function<void(const fs::path&)>& remove_old) {
  auto step = [&](const char* s) {
    if (options_.step) options_.step(s);
  };
  const HoldSignals hold;
  const bool exists = check();
  fs::path old;  // the previous directory after the swap
  if (!exists) {
    g_temp_set = 0;
    int e = ::renameat2(AT_FDCWD, temp_.c_str(), AT_FDCWD, path_.c_str(), RENAME_NOREPLACE) == 0 ? 0 : errno;
    if (e == EINVAL || e == ENOSYS) e = ::rename(temp_.c_str(), path_.c_str()) == 0 ? 0 : errno;
    if (e != 0) throw DataError(shown_, "cannot rename the new output into place: " + errno_text(e) + via_);
    published_ = true;
    return;
  }
  int e = 0;
  if (!options_.no_exchange) {
    e = ::renameat2(AT_FDCWD, temp_.c_str(), AT_FDCWD, path_.c_str(), RENAME_EXCHANGE) == 0 ? 0 : errno;
  }
  if (!options_.no_exchange && e == 0) {
    g_temp_set = 0;
    published_ = true;
    old = temp_;  // the names are swapped: the previous directory is at the temporary name
    step("swapped");
  } else if (options_.no_exchange || e == EINVAL || e == ENOSYS || e == ENOTSUP) {
    // No RENAME_EXCHANGE here: the previous directory aside, the new one in (a kill between
    // the two leaves both beside the path, and nothing at it).
    old = parent_ / ("." + name_ + ".old" + std::to_string(::getpid()));
    if (::rename(path_.c_str(), old.c_str()) != 0) {
      throw DataError(shown_, "cannot move the previous output aside: " + errno_text(errno) + via_);
    }
    step("aside");
    if (::rename(temp_.c_str(), path_.c_str()) != 0) {
      const int e2 = errno;
      ::rename(old.c_str(), path_.c_str());
      throw DataError(shown_, "cannot rename the new output into place: " + errno_text(e2) + via_);
    }
    g_temp_set = 0;
    published_ = true;
    step("swapped");
  } else {
    throw DataError(shown_, "cannot swap the new output into place: " + errno_text(e) + via_);
  }
  remove_old(old);
}

void for_each_leftover_dir(const fs::path& parent, const std::string& name,
                           const std::function<void(const fs::path&)>& visit) {
  std::error_code ec;
  std::vector<fs::path> found;
  for (fs::directory_iterator it(parent, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string n = it->path().filename().string();
    for (const std::string tag : {".tmp", ".old"}) {
      const std::string prefix = "." + name + tag;
      if (n.size() > prefix.size() && n.compare(0, prefix.size(), prefix) == 0 &&
          std::all_of(n.begin() + long(prefix.size()), n.end(), [](char c) { return c >= '0' && c <= '9'; })) {
        found.push_back(it->path());
      }
    }
  }
  std::sort(found.begin(), found.end());
  for (const fs::path& p : found) {
    if (!fs::is_directory(fs::symlink_status(p, ec))) continue;
    const int fd = lock_dir(p, false);
    if (fd < 0) continue;  // a live run's
    try {
      visit(p);
    } catch (...) {
      ::close(fd);
      throw;
    }
    ::close(fd);
  }
}

}  // namespace canopy::common
