// A directory written as a whole (detect's output directory, docs/decisions/detect.md "Output
// directory: replace only what detect wrote"). Built in a temporary directory
// `.<name>.tmp<pid>` beside the destination, flock'ed while its run lives and removed (flat) on
// an error or on kCleanupSignals (SIGINT, SIGTERM, SIGHUP, SIGPIPE, SIGXFSZ); published with
// renameat2(RENAME_EXCHANGE), so at every instant the old or the new complete directory is at
// the path, then the old one removed. Where the file system cannot exchange, two renames (the
// old one aside as `.<name>.old<pid>`, the new one in). Whether an existing directory may be
// replaced, how an old one is removed and which leftovers of killed runs are the caller's, the
// caller says.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

namespace canopy::common {

// AtomicDir's options.
struct AtomicDirOptions {
  // Called at "swapped" (the new directory at the path, the old one not yet removed) and
  // "aside" (fallback only: the old one moved aside, the new one not yet in): test hooks.
  std::function<void(const std::string& step)> step;
  bool no_exchange = false;  // use the two-rename fallback, as where RENAME_EXCHANGE is unsupported
};

class AtomicDir {
 public:
  using Options = AtomicDirOptions;

  // Creates and locks `.<name>.tmp<pid>` in `parent` (which must exist). `shown` and `via`
  // name the destination in messages (as given; " (the symbolic link points to '…')" or "").
  // Throws DataError naming the temporary directory.
  AtomicDir(const std::filesystem::path& parent, const std::string& name, std::string shown, std::string via,
            Options options = {});
  // Removes the temporary directory (flat) unless it was published.
  ~AtomicDir();
  AtomicDir(const AtomicDir&) = delete;
  AtomicDir& operator=(const AtomicDir&) = delete;

  const std::filesystem::path& temp() const { return temp_; }
  // Creates file `name` (plain, new) in the temporary directory holding `bytes`. Throws
  // DataError naming it.
  void write(const std::string& name, const std::string& bytes);
  // The same written in pieces: produce(sink) hands sink the file's bytes in order (never the
  // whole file at once); an exception from produce, or a failed write, leaves the file partial
  // in the temporary directory, which is never published then.
  using Sink = std::function<void(const char*, std::size_t)>;
  void write_pieces(const std::string& name, const std::function<void(const Sink&)>& produce);
  // Removes file `name` from the temporary directory. Throws DataError naming it.
  void remove(const std::string& name);

  // Moves the temporary directory to parent/name with kCleanupSignals held back until the end:
  // `check` (run first) throws when what is at the path may not be replaced and returns whether
  // something is there; `remove_old` then removes the previous directory (at its new name).
  // Throws DataError naming the destination when a rename fails.
  void publish(const std::function<bool()>& check,
               const std::function<void(const std::filesystem::path&)>& remove_old);

 private:
  std::filesystem::path parent_, path_, temp_;
  std::string name_, shown_, via_;
  Options options_;
  int fd_ = -1;  // the temporary directory, flock'ed
  bool published_ = false;
};

// Calls visit(p) for each leftover of a killed run beside parent/name: a directory
// `.<name>.tmp<digits>` or `.<name>.old<digits>` that no live run holds locked, in name order,
// holding its lock meanwhile.
void for_each_leftover_dir(const std::filesystem::path& parent, const std::string& name,
                           const std::function<void(const std::filesystem::path&)>& visit);

}  // namespace canopy::common
