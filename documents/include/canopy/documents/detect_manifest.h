// detect's proof of authorship of its output directory: manifest.json, format
// "canopy.detect_manifest", version 1 (docs/decisions/detect.md, "Output directory: replace only
// what detect wrote"). detect writes it last and reads a previous one before replacing a
// directory.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace canopy::documents {

inline constexpr const char* kDetectManifestFormat = "canopy.detect_manifest";
inline constexpr int kDetectManifestVersion = 1;

struct ManifestFile {
  std::string name;  // a plain file name of the directory (no '/', not . or ..), unique
  std::uint64_t bytes = 0;
  std::string sha256;  // hexadecimal, as written (detect compares it with the file's)
};

struct DetectManifest {
  std::string tool = "detect";
  std::vector<ManifestFile> files;  // in the order written
};

// The text detect writes (one space indent, a final newline).
std::string write_detect_manifest(const DetectManifest& m);

// Reads `text`, the contents of file `name`. Throws common::DataError naming `name`: not JSON,
// another format, a version other than 1, "files" missing or not an array, a file without a
// string name, an integer bytes >= 0 and a string sha256, a name that is not plain or repeats.
DetectManifest read_detect_manifest(const std::string& text, const std::string& name);

}  // namespace canopy::documents
