// Trajectory reader (formats/trajectory.h, issue 26): parse_trajectory on the bytes; a
// trajectory read must serialize to text that reads back and serializes identically, and
// interpolation at its ends and middle must not fail. Any other exception, crash, sanitizer
// report or allocation over -malloc_limit_mb is a finding.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "canopy/common/error.h"
#include "canopy/formats/trajectory.h"

namespace f = canopy::formats;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const f::Trajectory t = f::parse_trajectory(text, "fuzz.txt");
    const std::string once = f::serialize_trajectory(t);
    if (f::serialize_trajectory(f::parse_trajectory(once, "back.txt")) != once) std::abort();
    const double t0 = t.samples.front().time, t1 = t.samples.back().time;
    f::trajectory_sample(t, t0, 0, "fuzz.txt");
    f::trajectory_sample(t, t1, 0, "fuzz.txt");
    f::trajectory_position(t, t0 + (t1 - t0) / 2, 0, "fuzz.txt");
  } catch (const canopy::common::DataError&) {}
  return 0;
}
