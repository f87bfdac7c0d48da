// Atomic output: data goes to a temporary file in the destination's directory with the
// same extension ("<dir>/.<stem>.tmp<pid>-<n>.<ext>"); commit() renames it over the
// destination. If commit() is never reached (exception, SIGINT, SIGTERM, SIGHUP) the
// temporary file is removed, so a failed run leaves no output that make would trust.
// Path "-" writes to stdout directly (commit() flushes).
#pragma once

#include <fstream>
#include <memory>
#include <ostream>
#include <string>

namespace canopy::common {

class AtomicOutput {
 public:
  explicit AtomicOutput(const std::string& path);
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  std::ostream& stream();
  // Flushes, checks the stream, renames into place. Throws Error on failure.
  void commit();
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::string temp_;
  std::unique_ptr<std::ofstream> file_;
  bool committed_ = false;
};

// Whole-file convenience: writes `bytes` atomically to `path` ("-" = stdout).
void write_file_atomic(const std::string& path, const std::string& bytes);

// Reads a whole file ("-" = stdin) into memory. Throws DataError (missing, directory,
// unreadable).
std::string read_file(const std::string& path);

}  // namespace canopy::common
