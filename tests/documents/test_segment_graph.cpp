// documents/segment_graph.h: the segment graph ncut writes and gmatch, verify, areas and report
// read — round trip, skipped vertex lists, and malformed or hostile input (issue 12: each case
// broke the reader before), every error naming the file and the key.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <string>
#include <utility>

#include "canopy/common/error.h"
#include "canopy/documents/segment_graph.h"

using namespace canopy::documents;
using canopy::common::DataError;
using Catch::Contains;

namespace {

// The DataError's full message ("<name>: <cause>"); fails the test when `f` does not throw one.
template <typename F>
std::string data_error(F f, const std::string& name) {
  try {
    f();
  } catch (const DataError& e) {
    CHECK(std::string(e.what()).rfind(name + ": ", 0) == 0);
    return e.what();
  }
  FAIL("no DataError for " << name);
  return "";
}

const char* kGraph = R"({"format": "canopy.segment_graph", "version": VERSION,
 "provenance": {"tool": "ncut", "version": "0.1.0", "parameters": {}, "inputs": ["mesh.ply"]},
 "mesh": "mesh.ply",
 "segments": [{"segment_id": ID0, "vertex_count": 3, "area": AREA, "radii": [0.7, 0.4, 0.01],
               "thickness": 0.014, "elongation": 0.57, "centroid": [0.1, -0.3, 1.2], "normal": [0, 0, 1],
               "label": 1, "label_purity": 1, "vertices": [0, 1, 2]},
              {"segment_id": 1, "vertex_count": 3, "area": 0.8, "radii": [0.7, 0.4, 0.01],
               "thickness": 0.014, "elongation": 0.57, "centroid": [1, 0.2, 0.9], "normal": [1, 0, 0],
               "label": 1, "label_purity": 1, "vertices": [0, 1, 2]}],
 "adjacency": [{"a": 0, "b": 1, "shared_edges": 3}EDGES]})";

std::string graph(const std::string& version = "1", const std::string& id0 = "0",
                  const std::string& area = "1.5", const std::string& edges = "") {
  std::string s = kGraph;
  for (auto [k, v] :
       {std::pair<std::string, std::string>{"VERSION", version}, {"ID0", id0}, {"AREA", area}, {"EDGES", edges}}) {
    s.replace(s.find(k), k.size(), v);
  }
  return s;
}

std::string graph_error(const std::string& text, const std::string& name) {
  return data_error([&] { parse_segment_graph(text, name); }, name);
}

}  // namespace

TEST_CASE("segment graph: JSON round-trip, skipped vertex lists, version and format checks") {
  SegmentGraph g;
  g.provenance = {"ncut", "0.1.0", {{"r", "512mm"}}, {"mesh.ply"}};
  g.mesh = "mesh.ply";
  Segment s;
  s.segment_id = 3;
  s.vertex_count = 2;
  s.area = 1.0 / 3.0;
  s.radii = {1, 0.5, 0.1};
  s.normal = {0, 0, 1};
  s.vertices = {4, 9};
  g.segments.push_back(s);
  s.segment_id = 4;
  g.segments.push_back(s);
  g.adjacency.push_back({3, 4, 7});
  const std::string text = serialize_segment_graph(g);
  const SegmentGraph back = parse_segment_graph(text, "g.json");
  CHECK(back.segments.at(0).area == s.area);
  CHECK(back.segments.at(0).vertices == s.vertices);
  CHECK(back.adjacency.at(0).shared_edges == 7);
  CHECK(back.provenance.parameters == g.provenance.parameters);
  CHECK(serialize_segment_graph(back) == text);

  // Skipping the vertex lists (gmatch's modelbase): everything else as read, even a provenance
  // parameter named "vertices"; a list that is not even an array is not looked at.
  g.provenance.parameters.push_back({"vertices", "all"});
  const std::string with_param = serialize_segment_graph(g);
  const SegmentGraph skipped = parse_segment_graph(with_param, "g.json", GraphVertices::kSkip);
  REQUIRE(skipped.segments.size() == 2);
  CHECK(skipped.segments.at(1).vertices.empty());
  CHECK(skipped.segments.at(1).vertex_count == 2);
  CHECK(skipped.segments.at(1).area == s.area);
  CHECK(skipped.provenance.parameters == g.provenance.parameters);
  CHECK(skipped.adjacency.at(0).shared_edges == 7);
  std::string junk = with_param;
  junk.replace(junk.find("[\n    4,\n    9\n   ]"), 19, "\"junk\"");
  CHECK(parse_segment_graph(junk, "g.json", GraphVertices::kSkip).segments.size() == 2);
  CHECK_THROWS_WITH(parse_segment_graph(junk, "g.json"), Contains("vertices"));

  std::string v2 = text;
  v2.replace(v2.find("\"version\": 1"), 12, "\"version\": 2");
  CHECK_THROWS_WITH(parse_segment_graph(v2, "g.json"), Contains("version 2 is not supported"));
  CHECK_THROWS_AS(parse_segment_graph("{", "bad.json"), DataError);
  // An empty file says so (it said "not valid JSON: parse error at line 1, column 1: ...
  // unexpected end of input"), as the point readers' "empty file (not a PCD file)" do.
  CHECK_THROWS_WITH(parse_segment_graph("", "e.json"), "e.json: empty file (not a JSON document)");
  CHECK_THROWS_WITH(parse_segment_graph(" \n", "w.json"), "w.json: only white space (not a JSON document)");
}

TEST_CASE("JSON: numbers out of range, wrong integer types, and dangling or self edges are errors") {
  const SegmentGraph ok = parse_segment_graph(graph(), "g.json");
  CHECK(ok.segments.size() == 2);
  CHECK(ok.adjacency.size() == 1);
  const std::string big = graph_error(graph("1", "0", "1e400"), "area.json");
  CHECK_THAT(big, Contains("not valid JSON") && Contains("1e400"));
  CHECK(big.find("[json.exception") == std::string::npos);
  CHECK_THAT(graph_error(graph("4294967297"), "v.json"), Contains("version 4294967297 is not supported"));
  CHECK_THAT(graph_error(graph("1.0"), "v.json"), Contains("no integer \"version\""));
  CHECK_THAT(graph_error(graph("1", "1e20"), "id.json"),
             Contains("segments[0].segment_id must be an integer"));
  CHECK_THAT(graph_error(graph("1", "4294967296"), "id.json"),
             Contains("segments[0].segment_id 4294967296 is out of range"));
  CHECK_THAT(graph_error(graph("1", "-2"), "id.json"), Contains("segment_id -2 is out of range"));
  CHECK_THAT(graph_error(graph("1", "1"), "dup.json"), Contains("segment_id 1 appears twice"));
  CHECK_THAT(graph_error(graph("1", "0", "1.5", R"(, {"a": 0, "b": 99999, "shared_edges": 1})"), "d.json"),
             Contains("adjacency[1] (0, 99999) refers to segment 99999"));
  CHECK_THAT(graph_error(graph("1", "0", "1.5", R"(, {"a": 1, "b": 1, "shared_edges": 1})"), "s.json"),
             Contains("adjacency[1] joins segment 1 to itself"));
  CHECK_THAT(graph_error(graph("1", "0", "1.5", R"(, {"a": 1, "b": 0, "shared_edges": 1})"), "o.json"),
             Contains("needs a < b"));
  CHECK_THAT(graph_error(graph("1", "0", "1.5", R"(, {"a": 0, "b": 1, "shared_edges": 2})"), "t.json"),
             Contains("appears twice"));
  CHECK_THAT(graph_error(graph("1", "0", "\"big\""), "str.json"),
             Contains("segments[0].area must be a number"));
  const std::string nul = graph_error(std::string("{\"format\": \"x\0y\"}", 17), "nul.json");
  CHECK(std::strlen(nul.c_str()) == nul.size());
  CHECK_THAT(graph_error("ply\nformat ascii 1.0\n", "m.json"),
             Contains("this is a PLY file, not a JSON document"));
}

TEST_CASE("JSON: deep nesting is refused before parsing; nested values in messages are described") {
  // 30 000 levels used to overflow the stack (nlohmann copies values recursively).
  const std::string deep = std::string(30000, '[') + std::string(30000, ']');
  CHECK_THAT(graph_error("{\"format\": " + deep + "}", "deep.json"),
             Contains("nested deeper than 64 levels"));
  CHECK_THAT(graph_error(graph("1", deep), "deep-id.json"), Contains("nested deeper than 64 levels"));
  // Brackets inside strings do not count.
  std::string brackets = graph();
  brackets.replace(brackets.find("\"mesh\": \"mesh.ply\""), 18,
                   "\"mesh\": \"" + std::string(100, '[') + "\\\"\"");
  CHECK(parse_segment_graph(brackets, "b.json").mesh == std::string(100, '[') + "\"");
  const std::string shallow = "[[[[[[1]]]]]]";
  CHECK_THAT(graph_error(graph("1", shallow), "arr-id.json"),
             Contains("segment_id must be an integer, not an array"));
  CHECK_THAT(graph_error("{\"format\": " + shallow + "}", "arr.json"), Contains("format is an array"));
}

TEST_CASE(
    "segment graph: an array element that is not an object, a missing member: malformed, naming the place") {
  const std::string head = R"({"format": "canopy.segment_graph", "version": 1,
 "provenance": {"tool": "ncut", "version": "0.1.0", "parameters": {}, "inputs": []}, "mesh": "m.ply", )";
  CHECK(graph_error(head + R"("segments": [5], "adjacency": []})", "e.json") ==
        "e.json: malformed segment graph: segments[0] must be an object");
  CHECK(graph_error(head + R"("segments": [], "adjacency": [[0, 1]]})", "a.json") ==
        "a.json: malformed segment graph: adjacency[0] must be an object");
  const std::string no_prov = graph_error(
      R"({"format": "canopy.segment_graph", "version": 1, "mesh": "m.ply", "segments": [], "adjacency": []})",
      "p.json");
  CHECK_THAT(no_prov, Contains("p.json: malformed segment graph: ") && Contains("provenance"));
  CHECK(no_prov.find("[json.exception") == std::string::npos);
}
