// Atomic output. What happens depends on what the output path is (docs/decisions/hardening.md):
//   - "-": stdout; the data is written at commit().
//   - a regular file, or a path that does not exist yet: the data goes to a temporary file in
//     the destination's directory with the same extension ("<dir>/.<stem>.tmp<pid>-<n>.<ext>");
//     commit() renames it over the destination (keeping an existing file's permission bits).
//     If commit() is never reached (exception, SIGINT, SIGTERM, SIGHUP, SIGPIPE, SIGXFSZ) the
//     temporary file is removed, so a failed run leaves no output that make would trust.
//   - a symbolic link (also a chain, also a dangling one): resolved; the file it points to is
//     written as above, with the temporary file in the *target's* directory. The link stays.
//   - an existing FIFO, character or block device: written through (opened for writing, never
//     replaced, never unlinked); the data is held in memory and written at commit(), so a run
//     that fails before commit() writes nothing to it.
//   - a name of one of the process's own open descriptors (/dev/stdout, /dev/stderr,
//     /dev/fd/N, /proc/self/fd/N, /proc/<pid>/fd/N, also through links): that descriptor is
//     written, as "-" writes stdout: at its offset, appended to when it was opened O_APPEND
//     (`-o /dev/stdout >> log`), a pipe or a `>(cmd)` FIFO written through. Never reopened by
//     name (a pipe has none; reopening a file would truncate or overwrite it). It must be open
//     for writing.
//   - a directory or a socket: an error naming the path.
#pragma once

#include <memory>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

#include "canopy/common/share.h"  // share_dir(): where canopy's own files are

namespace canopy::common {

class AtomicOutput {
 public:
  explicit AtomicOutput(const std::string& path);
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  // Data written here is held until commit().
  std::ostream& stream();
  // Replaces what stream() holds (no copy): the whole-file form.
  void set_data(std::string bytes);
  // Writes the data and moves it into place. Throws DataError naming the path on failure.
  void commit();
  const std::string& path() const { return path_; }

  // commit() in two steps, for OutputSet: stage() writes every byte (the temporary file is then
  // complete and closed; a write-through target or stdout has received the data); publish()
  // renames the temporary file into place (nothing for write-through and stdout).
  void stage();
  void publish();

 private:
  enum class Mode { kStdout, kReplace, kWriteThrough };
  std::string path_;    // as given (messages)
  std::string target_;  // symbolic links resolved
  std::string temp_;    // kReplace only
  Mode mode_ = Mode::kReplace;
  int fd_ = -1;
  std::ostringstream buffer_;
  std::string data_;
  bool has_data_ = false;
  bool staged_ = false;
  bool committed_ = false;
  friend class OutputSet;
};

// Whole-file convenience: writes `bytes` atomically to `path` ("-" = stdout).
void write_file_atomic(const std::string& path, std::string bytes);

// Checks, before any work, that `path` can be written as an output ("-" always can): its
// directory exists and is writable, it is not a directory or a socket, its symbolic links
// resolve within 40 hops. Throws DataError naming the path and the problem (exit code 1).
void check_output(const std::string& path);

// True for "-", for a name of one of the process's own descriptors (/dev/stdout, /dev/fd/63)
// and for a path that (symbolic links followed) is an existing FIFO or character or block
// device: an output that is written through, not replaced. Such a path has no
// meaningful extension (`-o >(wc -c)` is /dev/fd/63): choose its format as for "-".
bool writes_through(const std::string& path);

// Canonical identity of an output path (symbolic links and "..", "." resolved; an existing
// file by device and inode), so two spellings of one file compare equal. "-" and the names of
// the process's own descriptors are what the descriptor is open on (so "-" and /dev/stdout
// are the same output).
std::string output_identity(const std::string& path);

// Several outputs of one run, atomic as a whole: add() every output before the work (each is
// checked as by check_output, and two outputs naming the same file, in any spelling, are a
// UsageError), then set() each one's data, then commit(): every temporary file is written
// completely first, then all are renamed into place with SIGINT/SIGTERM/SIGHUP/SIGPIPE held
// back, so an error or a signal leaves either every output or none (a write-through target,
// e.g. a FIFO, is written after all temporary files are complete and before any rename).
class OutputSet {
 public:
  // `option` names the output in messages ("-o", "--colored").
  void add(const std::string& path, const std::string& option);
  void set(const std::string& path, std::string bytes);
  void commit();

 private:
  struct Entry {
    std::string path, option, identity, data;
    bool has_data = false;
  };
  std::vector<Entry> entries_;
};

// Removes every temporary output file not yet committed. Async-signal-safe. (Each new
// temporary file (re)installs a handler that does this for SIGINT, SIGTERM, SIGHUP, SIGPIPE
// and SIGXFSZ unless the signal is ignored, e.g. SIGHUP under nohup, then calls the handler
// the program had installed, if any, or re-raises with the default action.)
void remove_pending_outputs() noexcept;

// The end of a signal handler that cleaned up: restores the signal's default action, unblocks
// it and raises it again, so the process dies of the signal (status 128 + sig for the shell).
// Async-signal-safe.
void reraise_with_default_action(int sig) noexcept;

// Reads a whole file ("-" = stdin) into memory. Throws DataError (missing, directory,
// unreadable).
std::string read_file(const std::string& path);

// Whether two paths name one file, or two readable files with the same bytes (sizes compared
// first); false when either cannot be read. What a copied tile directory's documents are checked
// by (verify's points and segments, collect's verdicts).
bool same_file_contents(const std::string& a, const std::string& b);

}  // namespace canopy::common
