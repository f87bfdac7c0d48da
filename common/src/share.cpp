#include "canopy/common/share.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <string>

#include "canopy/common/error.h"

namespace canopy::common {
namespace {

bool is_dir(const std::string& path) {
  struct stat st {};
  return stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

// Directory of the running executable ("" if /proc/self/exe cannot be read).
std::string exe_dir() {
  std::string buf(4096, '\0');
  const ssize_t n = readlink("/proc/self/exe", &buf[0], buf.size());
  if (n <= 0 || static_cast<std::size_t>(n) >= buf.size()) return "";
  buf.resize(static_cast<std::size_t>(n));
  const auto slash = buf.find_last_of('/');
  return slash == std::string::npos ? "" : buf.substr(0, slash);
}

}  // namespace

std::string share_dir() {
  if (const char* env = std::getenv("CANOPY_SHARE"); env != nullptr && *env != '\0') {
    if (!is_dir(env)) throw Error(std::string("CANOPY_SHARE=") + env + ": no such directory");
    return env;
  }
  const std::string exe = exe_dir();
  const std::string installed = exe + "/" CANOPY_SHARE_FROM_BIN;
  if (!exe.empty() && is_dir(installed)) return installed;
  if (is_dir(CANOPY_SHARE_DIR)) return CANOPY_SHARE_DIR;
  throw Error("cannot find canopy's share directory: tried $CANOPY_SHARE (unset), " +
              (exe.empty() ? std::string("<executable>") : exe) + "/" CANOPY_SHARE_FROM_BIN " and " +
              CANOPY_SHARE_DIR + "; set CANOPY_SHARE");
}

}  // namespace canopy::common
