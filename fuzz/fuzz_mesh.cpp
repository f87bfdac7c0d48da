// rangetrace's mesh importer (`rangetrace --model my.obj|.stl|.ply`): every input is parsed as
// OBJ, as STL (as given, and with the binary STL triangle count made consistent with its
// length so the binary reader is reached) and as PLY, each with z-up and y-up import, and
// converted to POV-Ray mesh2 code. It must succeed or throw common::DataError naming the
// file; any other exception, crash, sanitizer report or allocation over -malloc_limit_mb is a
// finding. Nothing is rendered (no POV-Ray). Seeds: fuzz/seeds/mesh/.
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>

#include "canopy/common/error.h"
#include "rangetrace/rangetrace.h"

namespace {

void import(const std::string& bytes, const std::string& ext, bool z_up) {
  canopy::rangetrace::MeshImport im;
  im.scale = z_up ? 1.0 : 1e-3;
  im.z_up = z_up;
  const std::string name = "fuzz." + ext;
  try {
    const std::string pov = canopy::rangetrace::mesh_file_to_pov(bytes, name, ext, im);
    if (pov.compare(0, 26, "#declare Vehicle = mesh2 {") != 0) std::abort();
  } catch (const canopy::common::DataError& e) {
    if (std::string(e.what()).find(name) == std::string::npos) std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  const bool z_up = size % 2 == 0;
  import(bytes, "obj", z_up);
  import(bytes, "ply", z_up);
  import(bytes, "stl", z_up);
  if (size >= 84) {
    std::string binary = bytes.substr(0, 84 + (size - 84) / 50 * 50);
    const std::uint32_t n = static_cast<std::uint32_t>((binary.size() - 84) / 50);
    std::memcpy(&binary[80], &n, 4);
    import(binary, "stl", !z_up);
  }
  return 0;
}
