// The .time file tools/stagerun writes beside every artifact it runs a stage for (GNU time's
// "%e %M %U %S"): "<wall seconds> <peak memory KiB> <user CPU seconds> <system CPU seconds>",
// e.g. out/sedan/circle/noise-8/samples.pcd.time holds "1.52 48212 1.40 0.08". Files written
// before the CPU columns hold the first two numbers only; they are read, without CPU.
#pragma once

#include <string>

namespace canopy::documents {

// Wall time, peak memory and CPU time of one stage run.
struct StageTime {
  double seconds = 0;         // wall
  double peak_mb = 0;         // KiB / 1024
  double user_seconds = 0;    // user CPU (0 when !has_cpu)
  double system_seconds = 0;  // system CPU (0 when !has_cpu)
  bool has_cpu = false;       // the file has the CPU columns (false: an older two-column file)
  bool present = false;       // the file exists
  double cpu_seconds() const { return user_seconds + system_seconds; }
};

// The time of the run that wrote `artifact`, from `artifact`.time. A missing file gives
// present = false: a stage that did not run is not counted. A file that is there must hold two
// or four numbers, each finite and >= 0; anything else (negative, nan, inf, words, another
// count, more than 4 KiB) throws common::DataError naming `artifact`.time.
StageTime read_stage_time(const std::string& artifact);

}  // namespace canopy::documents
