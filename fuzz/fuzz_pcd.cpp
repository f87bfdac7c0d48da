// PCD reader: parse_pcd on the bytes, and read_pcd (the chunked file reader) on the same bytes
// written to a file, must agree: both DataError, or the same cloud. A cloud read must write
// and read back. Any other exception, crash, sanitizer report, or allocation over
// -malloc_limit_mb is a finding.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "canopy/common/error.h"
#include "canopy/formats/pcd.h"

namespace {

using canopy::common::DataError;
using canopy::formats::PointCloud;

bool same(const PointCloud& a, const PointCloud& b) {
  if (a.size() != b.size() || a.names() != b.names() || !(a.types() == b.types())) return false;
  for (std::size_t c = 0; c < a.names().size(); ++c) {
    for (std::size_t i = 0; i < a.size(); ++i) {
      const double x = a.col(c)[i], y = b.col(c)[i];
      if (x != y && !(x != x && y != y)) return false;  // NaN == NaN here
    }
  }
  return true;
}

const std::string& temp_path() {
  static const std::string path = [] {
    const char* dir = std::getenv("TMPDIR");
    return std::string(dir ? dir : "/tmp") + "/canopy-fuzz-pcd-" + std::to_string(getpid()) + ".pcd";
  }();
  return path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  PointCloud mem, file;
  bool mem_ok = true, file_ok = true;
  try {
    mem = canopy::formats::parse_pcd(bytes, "fuzz.pcd");
  } catch (const DataError&) { mem_ok = false; }
  if (FILE* f = std::fopen(temp_path().c_str(), "wb")) {
    std::fwrite(bytes.data(), 1, bytes.size(), f);
    std::fclose(f);
    try {
      file = canopy::formats::read_pcd(temp_path());
    } catch (const DataError&) { file_ok = false; }
    std::remove(temp_path().c_str());
    if (mem_ok != file_ok || (mem_ok && !same(mem, file))) std::abort();  // the two readers disagree
  }
  if (mem_ok) {
    for (auto enc : {canopy::formats::PcdEncoding::binary, canopy::formats::PcdEncoding::binary_compressed,
                     canopy::formats::PcdEncoding::ascii}) {
      canopy::formats::PcdWriteOptions o;
      o.encoding = enc;
      const PointCloud back = canopy::formats::parse_pcd(canopy::formats::serialize_pcd(mem, o), "back.pcd");
      if (back.size() != mem.size() || back.names() != mem.names()) std::abort();
    }
  }
  return 0;
}
