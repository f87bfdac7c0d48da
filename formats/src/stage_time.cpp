#include "canopy/formats/stage_time.h"

#include <fstream>

namespace canopy::formats {

StageTime read_stage_time(const std::string& artifact) {
  StageTime t;
  std::ifstream in(artifact + ".time");
  double kib = 0;
  if (in >> t.seconds >> kib) {
    t.peak_mb = kib / 1024.0;
    t.present = true;
  }
  return t;
}

}  // namespace canopy::formats
