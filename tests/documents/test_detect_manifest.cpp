// documents/detect_manifest.h: detect's manifest.json (canopy.detect_manifest v1), written last
// into its output directory and read back before detect replaces one.
#include <catch2/catch.hpp>

#include <string>

#include <nlohmann/json.hpp>

#include "canopy/common/error.h"
#include "canopy/documents/detect_manifest.h"

using namespace canopy;
using Json = nlohmann::ordered_json;

namespace {

std::string refusal(const Json& doc) {
  try {
    documents::read_detect_manifest(doc.dump(), "out/manifest.json");
  } catch (const common::DataError& e) {
    CHECK(e.file() == "out/manifest.json");
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("detect manifest: the writer's text, byte for byte, read back") {
  documents::DetectManifest m;
  m.files = {{"c0001.pcd", 1234, "ab01"}, {"index.json", 0, "e3b0"}};
  const std::string text = documents::write_detect_manifest(m);
  CHECK(
      text ==
      "{\n \"format\": \"canopy.detect_manifest\",\n \"version\": 1,\n \"tool\": \"detect\",\n \"files\": [\n"
      "  {\n   \"name\": \"c0001.pcd\",\n   \"bytes\": 1234,\n   \"sha256\": \"ab01\"\n  },\n"
      "  {\n   \"name\": \"index.json\",\n   \"bytes\": 0,\n   \"sha256\": \"e3b0\"\n  }\n ]\n}\n");
  const documents::DetectManifest b = documents::read_detect_manifest(text, "m.json");
  CHECK(b.tool == "detect");
  REQUIRE(b.files.size() == 2);
  CHECK(b.files[0].name == "c0001.pcd");
  CHECK(b.files[0].bytes == 1234);
  CHECK(b.files[1].sha256 == "e3b0");
}

TEST_CASE("detect manifest: refusals name the file and the problem") {
  documents::DetectManifest m;
  m.files = {{"c0001.pcd", 1234, "ab01"}, {"index.json", 10, "e3b0"}};
  const Json good = Json::parse(documents::write_detect_manifest(m));
  CHECK(refusal(good).empty());
  auto with = [&](auto edit) {
    Json j = good;
    edit(j);
    return refusal(j);
  };
  CHECK_THAT(with([](Json& j) { j["format"] = "something"; }), Catch::Contains("canopy.detect_manifest"));
  CHECK_THAT(with([](Json& j) { j["version"] = 2; }), Catch::Contains("version 2"));
  CHECK_THAT(with([](Json& j) { j.erase("files"); }), Catch::Contains("manifest: missing \"files\""));
  CHECK_THAT(with([](Json& j) { j["files"] = "x"; }), Catch::Contains("files must be an array"));
  CHECK_THAT(with([](Json& j) { j["files"][1] = 3; }), Catch::Contains("files[1] must be an object"));
  CHECK_THAT(with([](Json& j) { j["files"][0].erase("sha256"); }),
             Catch::Contains("files[0]: missing \"sha256\""));
  CHECK_THAT(with([](Json& j) { j["files"][0]["bytes"] = -1; }),
             Catch::Contains("files[0].bytes must be an integer >= 0"));
  CHECK_THAT(with([](Json& j) { j["files"][0]["bytes"] = 1.5; }),
             Catch::Contains("files[0].bytes must be an integer >= 0"));
  CHECK_THAT(with([](Json& j) { j["files"][0]["name"] = 7; }),
             Catch::Contains("files[0].name must be a string"));
  CHECK_THAT(with([](Json& j) { j["files"][0]["name"] = "../x"; }),
             Catch::Contains("is not a plain file name"));
  CHECK_THAT(with([](Json& j) { j["files"][0]["name"] = ".."; }),
             Catch::Contains("is not a plain file name"));
  CHECK_THAT(with([](Json& j) { j["files"][1]["name"] = "c0001.pcd"; }),
             Catch::Contains("files[1].name \"c0001.pcd\" repeats"));
  CHECK_THAT(refusal(Json::parse("[]")), Catch::Contains("out/manifest.json"));
}
