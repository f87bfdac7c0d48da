// The .time file scripts/stage.sh writes beside every artifact it runs a stage for:
// "<wall seconds> <peak memory KiB>" (GNU time's %e %M), e.g. out/sedan/circle/noise-8/samples.pcd.time.
#pragma once

#include <string>

namespace canopy::formats {

// Wall time and peak memory of one stage run.
struct StageTime {
  double seconds = 0;
  double peak_mb = 0;  // KiB / 1024
  bool present = false;
};

// The time of the run that wrote `artifact`, from `artifact`.time. A missing or unreadable file
// (no two numbers first) gives present = false: a stage that did not run is not counted.
StageTime read_stage_time(const std::string& artifact);

}  // namespace canopy::formats
