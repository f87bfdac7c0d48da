// JSON documents (documents/): parse_segment_graph and parse_match_result on the bytes; a document read must
// serialize to text that reads back and serializes identically. Any other exception, crash,
// sanitizer report or allocation over -malloc_limit_mb is a finding.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "canopy/common/error.h"
#include "canopy/documents/match_result.h"
#include "canopy/documents/segment_graph.h"

using canopy::common::DataError;
namespace d = canopy::documents;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const d::SegmentGraph g = d::parse_segment_graph(text, "fuzz.json");
    const std::string once = d::serialize_segment_graph(g);
    if (d::serialize_segment_graph(d::parse_segment_graph(once, "back.json")) != once) std::abort();
  } catch (const DataError&) {}
  try {
    const d::MatchResult r = d::parse_match_result(text, "fuzz.json");
    const std::string once = d::serialize_match_result(r);
    if (d::serialize_match_result(d::parse_match_result(once, "back.json")) != once) std::abort();
  } catch (const DataError&) {}
  return 0;
}
