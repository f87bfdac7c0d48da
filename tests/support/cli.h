// Helpers shared by the tests that run tool binaries (header-only; tests/support has no .cpp,
// so it is not a test module of its own).
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace canopy::test {

// An empty directory CANOPY_TEST_TMP/<module>/<name>.
inline std::filesystem::path fresh_dir(const std::string& module, const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(CANOPY_TEST_TMP) / module / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// Runs a shell command with stderr captured in err_file; returns its exit status (-1 if it
// did not exit normally) and the captured stderr in *err.
inline int sh(const std::string& cmd, const std::filesystem::path& err_file, std::string* err) {
  const int status = std::system((cmd + " 2>" + err_file.string()).c_str());
  std::ifstream f(err_file);
  std::stringstream ss;
  ss << f.rdbuf();
  *err = ss.str();
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Runs a shell command; returns its exit status (-1 if it did not exit normally).
inline int run(const std::string& cmd) {
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

inline bool exists(const std::filesystem::path& p) { return std::filesystem::exists(p); }

// Writes `text` to `p`, creating its parent directories (fixtures of hand-made files).
inline void write_file(const std::filesystem::path& p, const std::string& text) {
  std::filesystem::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

// The whole of a text file ("" when it cannot be read).
inline std::string read_text(const std::filesystem::path& p) {
  std::ifstream f(p);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

}  // namespace canopy::test
