// JSON readers: parse_segment_graph and parse_match_result on the bytes; a document read must
// serialize to text that reads back and serializes identically. Any other exception, crash,
// sanitizer report or allocation over -malloc_limit_mb is a finding.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "canopy/common/error.h"
#include "canopy/formats/match_result.h"
#include "canopy/formats/segment_graph.h"

using canopy::common::DataError;
namespace f = canopy::formats;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const f::SegmentGraph g = f::parse_segment_graph(text, "fuzz.json");
    const std::string once = f::serialize_segment_graph(g);
    if (f::serialize_segment_graph(f::parse_segment_graph(once, "back.json")) != once) std::abort();
  } catch (const DataError&) {}
  try {
    const f::MatchResult r = f::parse_match_result(text, "fuzz.json");
    const std::string once = f::serialize_match_result(r);
    if (f::serialize_match_result(f::parse_match_result(once, "back.json")) != once) std::abort();
  } catch (const DataError&) {}
  return 0;
}
