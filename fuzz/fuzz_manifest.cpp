// The manifests make writes (documents/experiment_manifest.h, documents/tile_list.h): both
// readers on the bytes; a manifest read must write text that reads back and writes identically.
// Any other exception, crash, sanitizer report or allocation over -malloc_limit_mb is a finding.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "canopy/common/error.h"
#include "canopy/documents/experiment_manifest.h"
#include "canopy/documents/tile_list.h"

namespace d = canopy::documents;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const std::string once = d::write_experiment_manifest(d::parse_experiment_manifest(text, "fuzz.txt"));
    if (d::write_experiment_manifest(d::parse_experiment_manifest(once, "back.txt")) != once) std::abort();
  } catch (const canopy::common::DataError&) {}
  try {
    const std::string once = d::write_tile_list(d::parse_tile_list(text, "fuzz.txt"));
    if (d::write_tile_list(d::parse_tile_list(once, "back.txt")) != once) std::abort();
  } catch (const canopy::common::DataError&) {}
  return 0;
}
