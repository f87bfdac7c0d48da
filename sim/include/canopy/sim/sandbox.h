// Internal: confining POV-Ray (docs/decisions/sandbox.md). Two layers:
//  1. every POV-Ray process runs in a bubblewrap (bwrap) jail: new user, mount, PID, IPC, UTS,
//     network and cgroup namespaces, no capabilities, a read-only view of /usr, POV-Ray's
//     configuration, canopy's built-in models and exactly the user files that layer 2
//     approved, and one writable directory (rangetrace's private one);
//  2. a user include (--model x.inc, a tile's `vehicle = x.inc ...`) is checked lexically
//     before POV-Ray sees it: file names must be literal, relative and without "..", nothing
//     is written, and the files it reads must lie in its own directory.
// CANOPY_POVRAY_SANDBOX selects: "auto" (default: bwrap, required for user includes; canopy's
// own scenes run unconfined, with a warning, where bwrap cannot create namespaces), "bwrap"
// (required for every run) or "off" (no bwrap: layer 2 alone, a documented opt-out, warned).
#pragma once

#include <string>
#include <vector>

#include "canopy/common/printable.h"

namespace canopy::sim {

enum class SandboxMode { kAuto, kBwrap, kOff };

// The mode from CANOPY_POVRAY_SANDBOX; a UsageError for any other value.
SandboxMode sandbox_mode();

// Layer 2: checks the user include `dir`/`file` and every file of `dir` it includes. Throws
// common::DataError "<file>: line <n>: <why>" for the first violation. Returns the paths
// (spelled under `dir`, which must be absolute and real) of the files of `dir` that POV-Ray
// may read: the include, its includes, and every existing file of `dir` (or below) that a
// string literal names. `unconfined` (mode off) also refuses the macros of POV-Ray's standard
// includes that write or include a file whose name the caller gives (they would escape the
// check when nothing else confines POV-Ray).
std::vector<std::string> check_user_include(const std::string& dir, const std::string& file, bool unconfined);

// A POV-Ray command ready to exec: the program (absolute), its argv and environment.
struct Command {
  std::string program;
  std::vector<std::string> argv;
  std::vector<std::string> env;
};

// Layer 1: `povray_args` (without the program) run as `povray` (the --povray option: a name
// looked up on PATH or a path), confined per the mode, with `workdir` (absolute) as its
// writable working directory and `readable` (absolute paths) visible read-only.
// `user_code`: a user include is part of the scene, so confinement is required unless the
// mode is off. Throws common::Error when confinement is required and bwrap cannot provide it
// (bwrap missing, or it cannot create namespaces), naming the cause and the opt-out. The
// one-time check that bwrap works (per process) runs `true` in the jail, logging to `workdir`.
Command povray_command(const std::string& povray, const std::vector<std::string>& povray_args,
                       const std::string& workdir, const std::vector<std::string>& readable, bool user_code);

// Text from a user file (a name, a token) for a message: control bytes as \xNN (common/printable.h).
using common::printable;

}  // namespace canopy::sim
