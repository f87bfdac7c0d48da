// One error hierarchy for every canopy tool. Exceptions are caught in one place
// (canopy::common::Tool::run), which prints "<tool>: error: <message>" and maps the
// exception type to the exit code: UsageError -> 2, every other Error -> 1.
#pragma once

#include <new>
#include <stdexcept>
#include <string>

namespace canopy::common {

// Base: a runtime failure (exit code 1).
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
  virtual int exit_code() const { return 1; }
};

// The command line is wrong (exit code 2).
class UsageError : public Error {
 public:
  explicit UsageError(const std::string& message) : Error(message) {}
  int exit_code() const override { return 2; }
};

// A file is unreadable, malformed or holds data a stage cannot use (exit code 1).
// The message reads "<file>: <cause>".
class DataError : public Error {
 public:
  DataError(const std::string& file, const std::string& cause);
  const std::string& file() const { return file_; }
  const std::string& cause() const { return cause_; }

 private:
  std::string file_;
  std::string cause_;
};

// Display name of a path for messages: "-" is shown as "<stdin>" / "<stdout>".
std::string display_name(const std::string& path, bool output = false);

// Runs f() and returns what it returns; any exception but a UsageError, a DataError (which
// names its file already) and std::bad_alloc comes out as a DataError naming `path` (its
// display_name). For a stage whose every failure is about its one input: fitvox's "voxel index
// overflow: point 0 has x = 1e+30 m" and ncut's "point set extent exceeds 2^20 affinity radii"
// named no file.
template <typename F>
decltype(auto) naming_input(const std::string& path, F&& f) {
  try {
    return f();
  } catch (const UsageError&) { throw; } catch (const DataError&) {
    throw;
  } catch (const std::bad_alloc&) { throw; } catch (const std::exception& e) {
    throw DataError(display_name(path), e.what());
  }
}

}  // namespace canopy::common
