#include "canopy/documents/segment_graph.h"

#include <nlohmann/json.hpp>
#include <set>
#include <utility>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/formats/json_document.h"
#include "canopy/formats/json_fields.h"
#include "members.h"

namespace canopy::documents {
namespace {

using formats::finite_for_writing;
using formats::MalformedField;
using members::Json;

Json vec3_json(const Vec3& v, const char* what) {
  return Json::array(
      {finite_for_writing(v[0], what), finite_for_writing(v[1], what), finite_for_writing(v[2], what)});
}

}  // namespace

std::string serialize_segment_graph(const SegmentGraph& g) {
  Json segs = Json::array();
  for (const auto& s : g.segments) {
    segs.push_back(Json{{"segment_id", s.segment_id},
                        {"vertex_count", s.vertex_count},
                        {"area", finite_for_writing(s.area, "area")},
                        {"radii", vec3_json(s.radii, "radii")},
                        {"thickness", finite_for_writing(s.thickness, "thickness")},
                        {"elongation", finite_for_writing(s.elongation, "elongation")},
                        {"centroid", vec3_json(s.centroid, "centroid")},
                        {"normal", vec3_json(s.normal, "normal")},
                        {"label", s.label},
                        {"label_purity", finite_for_writing(s.label_purity, "label_purity")},
                        {"vertices", s.vertices}});
  }
  Json adj = Json::array();
  for (const auto& e : g.adjacency)
    adj.push_back(Json{{"a", e.a}, {"b", e.b}, {"shared_edges", e.shared_edges}});
  Json j{{"format", kSegmentGraphFormat},
         {"version", kSegmentGraphVersion},
         {"provenance", formats::provenance_json(g.provenance)},
         {"mesh", g.mesh},
         {"segments", segs},
         {"adjacency", adj}};
  return formats::json_document_text(j);
}

SegmentGraph parse_segment_graph(const std::string& text, const std::string& name, GraphVertices vertices) {
  // Skipping: a segment's "vertices" key (depth 3 inside the top-level "segments" array; a
  // provenance parameter of that name, also at depth 3, is kept) is dropped while parsing, so
  // its numbers never become JSON values (most of a graph's bytes).
  const bool skip = vertices == GraphVertices::kSkip;
  bool in_segments = false;
  const auto drop_vertices = [&in_segments](int depth, Json::parse_event_t event, Json& parsed) {
    if (event != Json::parse_event_t::key) return true;
    if (depth == 1) in_segments = parsed == "segments";
    return !(in_segments && depth == 3 && parsed == "vertices");
  };
  const Json j =
      formats::open_json_document(text, name, kSegmentGraphFormat,
                                  skip ? Json::parser_callback_t(drop_vertices) : Json::parser_callback_t());
  SegmentGraph g;
  try {
    g.provenance = formats::json_provenance(j.at("provenance"));
    g.mesh = formats::json_string_at(j, "mesh", "");
    std::set<int> ids;
    const Json& segs = formats::json_array_at(j, "segments", "");
    for (std::size_t k = 0; k < segs.size(); ++k) {
      const std::string w = members::item("", "segments", k);
      const Json& s = members::item_object(segs[k], w);
      Segment seg;
      seg.segment_id = formats::json_int_at(s, "segment_id", w, 0);
      if (!ids.insert(seg.segment_id).second) {
        throw MalformedField(w + "segment_id " + std::to_string(seg.segment_id) + " appears twice");
      }
      seg.vertex_count = formats::json_int_at(s, "vertex_count", w, 0);
      seg.area = formats::json_number_at(s, "area", w);
      seg.radii = formats::json_vec3_at(s, "radii", w);
      seg.thickness = formats::json_number_at(s, "thickness", w);
      seg.elongation = formats::json_number_at(s, "elongation", w);
      seg.centroid = formats::json_vec3_at(s, "centroid", w);
      seg.normal = formats::json_vec3_at(s, "normal", w);
      seg.label = formats::json_int_at(s, "label", w);
      seg.label_purity = formats::json_number_at(s, "label_purity", w);
      if (!skip) {
        const Json& verts = formats::json_array_at(s, "vertices", w);
        seg.vertices.reserve(verts.size());
        for (const auto& v : verts)
          seg.vertices.push_back(static_cast<int>(formats::json_integer(v, w + "vertices[]", 0)));
      }
      g.segments.push_back(std::move(seg));
    }
    std::set<std::pair<int, int>> edges;
    const Json& adj = formats::json_array_at(j, "adjacency", "");
    for (std::size_t k = 0; k < adj.size(); ++k) {
      const std::string w = members::item("", "adjacency", k);
      const Json& e = members::item_object(adj[k], w);
      const SegmentEdge edge{formats::json_int_at(e, "a", w, 0), formats::json_int_at(e, "b", w, 0),
                             formats::json_int_at(e, "shared_edges", w, 0)};
      const std::string pair = " (" + std::to_string(edge.a) + ", " + std::to_string(edge.b) + ")";
      if (edge.a == edge.b)
        throw MalformedField(w.substr(0, w.size() - 1) + " joins segment " + std::to_string(edge.a) +
                             " to itself");
      if (edge.a > edge.b) throw MalformedField(w.substr(0, w.size() - 1) + pair + " needs a < b");
      for (int id : {edge.a, edge.b}) {
        if (!ids.count(id))
          throw MalformedField(w.substr(0, w.size() - 1) + pair + " refers to segment " + std::to_string(id) +
                               ", which is not in segments");
      }
      if (!edges.insert({edge.a, edge.b}).second)
        throw MalformedField(w.substr(0, w.size() - 1) + pair + " appears twice");
      g.adjacency.push_back(edge);
    }
  } catch (...) { members::rethrow_malformed(name, "segment graph"); }
  return g;
}

SegmentGraph read_segment_graph(const std::string& path, GraphVertices vertices) {
  try {
    return parse_segment_graph(common::read_file(path), path, vertices);
  } catch (const common::DataError& e) {
    if (e.file() == path) throw;
    throw common::DataError(path, e.what());
  } catch (const std::exception& e) { throw common::DataError(path, e.what()); }
}

void write_segment_graph(const SegmentGraph& graph, const std::string& path) {
  common::write_file_atomic(path, serialize_segment_graph(graph));
}

}  // namespace canopy::documents
