#include "canopy/common/atomic_file.h"

#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <iterator>
#include <mutex>
#include <sstream>

#include "canopy/common/error.h"

namespace canopy::common {
namespace {

// Temporary files still pending, removed by the signal handler. Fixed storage so the
// handler only touches async-signal-safe memory.
constexpr int kMaxPending = 32;
constexpr int kMaxPath = 4096;
char g_pending[kMaxPending][kMaxPath];
std::atomic<bool> g_used[kMaxPending];
std::once_flag g_handlers_once;
std::atomic<unsigned> g_counter{0};

extern "C" void remove_pending_and_reraise(int sig) {
  for (int i = 0; i < kMaxPending; ++i) {
    if (g_used[i].load()) unlink(g_pending[i]);
  }
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

void install_handlers() {
  for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) {
    struct sigaction sa {};
    sa.sa_handler = remove_pending_and_reraise;
    sigemptyset(&sa.sa_mask);
    sigaction(sig, &sa, nullptr);
  }
}

int register_pending(const std::string& path) {
  std::call_once(g_handlers_once, install_handlers);
  if (path.size() >= static_cast<std::size_t>(kMaxPath)) return -1;
  for (int i = 0; i < kMaxPending; ++i) {
    if (!g_used[i].load()) {
      std::memcpy(g_pending[i], path.c_str(), path.size() + 1);
      g_used[i].store(true);
      return i;
    }
  }
  return -1;
}

void unregister_pending(const std::string& path) {
  for (int i = 0; i < kMaxPending; ++i) {
    if (g_used[i].load() && path == g_pending[i]) {
      g_used[i].store(false);
      return;
    }
  }
}

std::string temp_name_for(const std::string& path) {
  const auto slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? "" : path.substr(0, slash + 1);
  const std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
  const auto dot = base.find_last_of('.');
  const std::string stem = dot == std::string::npos || dot == 0 ? base : base.substr(0, dot);
  const std::string ext = dot == std::string::npos || dot == 0 ? "" : base.substr(dot);
  return dir + "." + stem + ".tmp" + std::to_string(getpid()) + "-" +
         std::to_string(g_counter.fetch_add(1)) + ext;
}

}  // namespace

AtomicOutput::AtomicOutput(const std::string& path) : path_(path) {
  if (path_.empty()) throw UsageError("empty output path");
  if (path_ == "-") return;
  struct stat st {};
  if (stat(path_.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) {
    throw DataError(path_, "is a directory, not an output file");
  }
  temp_ = temp_name_for(path_);
  register_pending(temp_);
  file_ = std::make_unique<std::ofstream>(temp_, std::ios::binary | std::ios::trunc);
  if (!*file_) {
    unregister_pending(temp_);
    throw DataError(path_, std::string("cannot create output: ") + std::strerror(errno));
  }
}

AtomicOutput::~AtomicOutput() {
  if (!committed_ && !temp_.empty()) {
    file_.reset();
    std::remove(temp_.c_str());
    unregister_pending(temp_);
  }
}

std::ostream& AtomicOutput::stream() {
  if (path_ == "-") return std::cout;
  return *file_;
}

void AtomicOutput::commit() {
  if (committed_) return;
  if (path_ == "-") {
    std::cout.flush();
    if (!std::cout) throw DataError(path_, "write to standard output failed");
    committed_ = true;
    return;
  }
  file_->flush();
  const bool ok = static_cast<bool>(*file_);
  file_->close();
  if (!ok || file_->fail()) {
    throw DataError(path_, "write failed (disk full?)");
  }
  if (std::rename(temp_.c_str(), path_.c_str()) != 0) {
    throw DataError(path_, std::string("cannot move output into place: ") + std::strerror(errno));
  }
  unregister_pending(temp_);
  committed_ = true;
}

void write_file_atomic(const std::string& path, const std::string& bytes) {
  AtomicOutput out(path);
  out.stream().write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.commit();
}

std::string read_file(const std::string& path) {
  if (path == "-") {
    std::ostringstream ss;
    ss << std::cin.rdbuf();
    return ss.str();
  }
  struct stat st {};
  if (stat(path.c_str(), &st) != 0) {
    throw DataError(path, std::string("cannot open: ") + std::strerror(errno));
  }
  if (S_ISDIR(st.st_mode)) throw DataError(path, "is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw DataError(path, std::string("cannot open: ") + std::strerror(errno));
  std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw DataError(path, "read error");
  return data;
}

}  // namespace canopy::common
