#include "canopy/documents/detect_manifest.h"

#include <set>

#include "canopy/common/error.h"
#include "canopy/formats/json_document.h"
#include "members.h"

namespace canopy::documents {
namespace {

using namespace members;  // NOLINT(google-build-using-namespace): the document's member helpers

bool plain(const std::string& n) {
  return !n.empty() && n != "." && n != ".." && n.find('/') == std::string::npos &&
         n.find('\0') == std::string::npos;
}

}  // namespace

std::string write_detect_manifest(const DetectManifest& m) {
  Json files = Json::array();
  for (const ManifestFile& f : m.files)
    files.push_back(Json{{"name", f.name}, {"bytes", f.bytes}, {"sha256", f.sha256}});
  const Json j{{"format", kDetectManifestFormat},
               {"version", kDetectManifestVersion},
               {"tool", m.tool},
               {"files", files}};
  return j.dump(1) + "\n";
}

DetectManifest read_detect_manifest(const std::string& text, const std::string& name) {
  const Json j =
      formats::open_json_document(text, name, kDetectManifestFormat, nullptr, kDetectManifestVersion);
  DetectManifest m;
  try {
    const Json* tool = optional(j, "tool");
    m.tool = tool ? members::text(*tool, "tool") : "";
    const Json& files = array(at(j, "files", "manifest"), "files");
    std::set<std::string> seen;
    for (std::size_t i = 0; i < files.size(); ++i) {
      const std::string w = "files[" + std::to_string(i) + "]";
      const Json& f = object(files[i], w);
      ManifestFile e;
      e.name = members::text(at(f, "name", w), w + ".name");
      const Json& bytes = at(f, "bytes", w);
      if (!bytes.is_number_unsigned() && !(bytes.is_number_integer() && bytes.get<long long>() >= 0))
        throw Malformed(w + ".bytes must be an integer >= 0, not " + describe(bytes));
      e.bytes = bytes.get<std::uint64_t>();
      e.sha256 = members::text(at(f, "sha256", w), w + ".sha256");
      if (!plain(e.name))
        throw Malformed(w + ".name " + describe(at(f, "name", w)) + " is not a plain file name");
      if (!seen.insert(e.name).second) throw Malformed(w + ".name \"" + e.name + "\" repeats");
      m.files.push_back(std::move(e));
    }
  } catch (const Malformed& e) { throw common::DataError(name, e.what()); }
  return m;
}

}  // namespace canopy::documents
