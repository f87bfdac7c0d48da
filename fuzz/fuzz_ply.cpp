// PLY reader: parse_ply on the bytes; a mesh read must write (binary, ascii, scalar_ names) and
// read back with the same vertices and faces. Any other exception, crash, sanitizer report or
// allocation over -malloc_limit_mb is a finding.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "canopy/common/error.h"
#include "canopy/formats/ply.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  canopy::formats::Mesh mesh;
  try {
    mesh = canopy::formats::parse_ply(bytes, "fuzz.ply");
  } catch (const canopy::common::DataError&) { return 0; }
  for (int mode = 0; mode < 3; ++mode) {
    canopy::formats::PlyWriteOptions o;
    o.ascii = mode == 1;
    o.scalar_prefix = mode == 2;
    const canopy::formats::Mesh back =
        canopy::formats::parse_ply(canopy::formats::serialize_ply(mesh, o), "back.ply");
    if (back.vertices.size() != mesh.vertices.size() || back.faces != mesh.faces) std::abort();
  }
  return 0;
}
