#include "canopy/formats/match_result.h"
#include "canopy/formats/segment_graph.h"
#include "canopy/formats/json_document.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "canopy/common/atomic_file.h"
#include "binary_io.h"
#include "canopy/common/error.h"

namespace canopy::formats {
namespace {

using common::DataError;
using Json = nlohmann::ordered_json;

constexpr const char* kGraphFormat = "canopy.segment_graph";
constexpr const char* kMatchFormat = "canopy.match_result";
constexpr int kVersion = 1;

double finite(double v, const char* what) {
  if (!std::isfinite(v)) throw common::Error(std::string("refusing to write non-finite ") + what);
  return v;
}

Json vec3(const Vec3& v, const char* what) {
  return Json::array({finite(v[0], what), finite(v[1], what), finite(v[2], what)});
}

// A malformed value: the reader adds the file name and where ("segments[3].area: ...").
struct Malformed : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A value for a message: scalars as JSON text (cut, NUL-safe); arrays and objects by kind only
// (dumping a 30 000-deep nested array would recurse 30 000 frames).
std::string describe(const Json& j) {
  if (j.is_array()) return "an array";
  if (j.is_object()) return "an object";
  return detail::quote(j.dump(), 40);
}

// An integer within [lo, hi]; 3.0, 1e20 or "3" are not accepted (they would be cast silently).
long long int_from(const Json& j, const std::string& what, long long lo = std::numeric_limits<int>::min(),
                   long long hi = std::numeric_limits<int>::max()) {
  long long v = 0;
  if (j.is_number_unsigned()) {
    const auto u = j.get<std::uint64_t>();
    if (u > static_cast<std::uint64_t>(hi)) throw Malformed(what + " " + j.dump() + " is out of range");
    v = static_cast<long long>(u);
  } else if (j.is_number_integer()) {
    v = j.get<std::int64_t>();
  } else {
    throw Malformed(what + " must be an integer, not " + describe(j));
  }
  if (v < lo || v > hi) {
    throw Malformed(what + " " + j.dump() + " is out of range [" + std::to_string(lo) + ", " +
                    std::to_string(hi) + "]");
  }
  return v;
}

int int_at(const Json& obj, const char* key, const std::string& where,
           long long lo = std::numeric_limits<int>::min()) {
  return static_cast<int>(int_from(obj.at(key), where + key, lo));
}

double double_at(const Json& obj, const char* key, const std::string& where) {
  const Json& j = obj.at(key);
  if (!j.is_number()) throw Malformed(where + key + " must be a number, not " + describe(j));
  const double v = j.get<double>();
  if (!std::isfinite(v)) throw Malformed(where + key + " is not finite");
  return v;
}

std::string string_at(const Json& obj, const char* key, const std::string& where) {
  const Json& j = obj.at(key);
  if (!j.is_string()) throw Malformed(where + key + " must be a string");
  return j.get<std::string>();
}

const Json& array_at(const Json& obj, const char* key, const std::string& where) {
  const Json& j = obj.at(key);
  if (!j.is_array()) throw Malformed(where + key + " must be an array");
  return j;
}

Vec3 vec3_from(const Json& obj, const char* key, const std::string& where) {
  const Json& j = obj.at(key);
  if (!j.is_array() || j.size() != 3) throw Malformed(where + key + " must be an array of 3 numbers");
  Vec3 v{};
  for (std::size_t i = 0; i < 3; ++i) {
    if (!j[i].is_number()) throw Malformed(where + key + " must be an array of 3 numbers");
    v[i] = j[i].get<double>();
  }
  return v;
}

std::string library_text(const std::exception& e) {
  std::string w = e.what();
  if (w.rfind("[json.exception.", 0) == 0 && w.find("] ") != std::string::npos)
    w = w.substr(w.find("] ") + 2);
  return w;
}

Provenance provenance_from(const Json& j) {
  Provenance p;
  if (!j.is_object()) throw Malformed("provenance must be an object");
  p.tool = string_at(j, "tool", "provenance.");
  p.version = string_at(j, "version", "provenance.");
  const Json& params = j.at("parameters");
  if (!params.is_object()) throw Malformed("provenance.parameters must be an object");
  for (const auto& [k, v] : params.items()) {
    if (!v.is_string()) throw Malformed("provenance.parameters." + k + " must be a string");
    p.parameters.emplace_back(k, v.get<std::string>());
  }
  for (const auto& in : array_at(j, "inputs", "provenance.")) {
    if (!in.is_string()) throw Malformed("provenance.inputs must be strings");
    p.inputs.push_back(in.get<std::string>());
  }
  return p;
}

std::string dump(const Json& j) { return j.dump(1) + "\n"; }

}  // namespace

std::string serialize_segment_graph(const SegmentGraph& g) {
  Json segs = Json::array();
  for (const auto& s : g.segments) {
    segs.push_back(Json{{"segment_id", s.segment_id},
                        {"vertex_count", s.vertex_count},
                        {"area", finite(s.area, "area")},
                        {"radii", vec3(s.radii, "radii")},
                        {"thickness", finite(s.thickness, "thickness")},
                        {"elongation", finite(s.elongation, "elongation")},
                        {"centroid", vec3(s.centroid, "centroid")},
                        {"normal", vec3(s.normal, "normal")},
                        {"label", s.label},
                        {"label_purity", finite(s.label_purity, "label_purity")},
                        {"vertices", s.vertices}});
  }
  Json adj = Json::array();
  for (const auto& e : g.adjacency)
    adj.push_back(Json{{"a", e.a}, {"b", e.b}, {"shared_edges", e.shared_edges}});
  Json j{{"format", kGraphFormat}, {"version", kVersion}, {"provenance", provenance_json(g.provenance)},
         {"mesh", g.mesh},         {"segments", segs},    {"adjacency", adj}};
  return dump(j);
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
  const Json j = open_json_document(
      text, name, kGraphFormat, skip ? Json::parser_callback_t(drop_vertices) : Json::parser_callback_t());
  SegmentGraph g;
  try {
    g.provenance = provenance_from(j.at("provenance"));
    g.mesh = string_at(j, "mesh", "");
    std::set<int> ids;
    const Json& segs = array_at(j, "segments", "");
    for (std::size_t k = 0; k < segs.size(); ++k) {
      const Json& s = segs[k];
      const std::string w = "segments[" + std::to_string(k) + "].";
      if (!s.is_object()) throw Malformed(w.substr(0, w.size() - 1) + " must be an object");
      Segment seg;
      seg.segment_id = int_at(s, "segment_id", w, 0);
      if (!ids.insert(seg.segment_id).second) {
        throw Malformed(w + "segment_id " + std::to_string(seg.segment_id) + " appears twice");
      }
      seg.vertex_count = int_at(s, "vertex_count", w, 0);
      seg.area = double_at(s, "area", w);
      seg.radii = vec3_from(s, "radii", w);
      seg.thickness = double_at(s, "thickness", w);
      seg.elongation = double_at(s, "elongation", w);
      seg.centroid = vec3_from(s, "centroid", w);
      seg.normal = vec3_from(s, "normal", w);
      seg.label = int_at(s, "label", w);
      seg.label_purity = double_at(s, "label_purity", w);
      if (!skip) {
        const Json& verts = array_at(s, "vertices", w);
        seg.vertices.reserve(verts.size());
        for (const auto& v : verts)
          seg.vertices.push_back(static_cast<int>(int_from(v, w + "vertices[]", 0)));
      }
      g.segments.push_back(std::move(seg));
    }
    std::set<std::pair<int, int>> edges;
    const Json& adj = array_at(j, "adjacency", "");
    for (std::size_t k = 0; k < adj.size(); ++k) {
      const Json& e = adj[k];
      const std::string w = "adjacency[" + std::to_string(k) + "].";
      if (!e.is_object()) throw Malformed(w.substr(0, w.size() - 1) + " must be an object");
      const SegmentEdge edge{int_at(e, "a", w, 0), int_at(e, "b", w, 0), int_at(e, "shared_edges", w, 0)};
      const std::string pair = " (" + std::to_string(edge.a) + ", " + std::to_string(edge.b) + ")";
      if (edge.a == edge.b)
        throw Malformed(w.substr(0, w.size() - 1) + " joins segment " + std::to_string(edge.a) + " to itself");
      if (edge.a > edge.b) throw Malformed(w.substr(0, w.size() - 1) + pair + " needs a < b");
      for (int id : {edge.a, edge.b}) {
        if (!ids.count(id))
          throw Malformed(w.substr(0, w.size() - 1) + pair + " refers to segment " + std::to_string(id) +
                          ", which is not in segments");
      }
      if (!edges.insert({edge.a, edge.b}).second)
        throw Malformed(w.substr(0, w.size() - 1) + pair + " appears twice");
      g.adjacency.push_back(edge);
    }
  } catch (const DataError&) { throw; } catch (const Malformed& e) {
    throw DataError(name, std::string("malformed segment graph: ") + e.what());
  } catch (const std::exception& e) {
    throw DataError(name, "malformed segment graph: " + detail::quote(library_text(e), 200));
  }
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

double match_margin(const MatchResult& r) {
  if (r.models.size() < 2) return std::numeric_limits<double>::quiet_NaN();
  std::vector<const ModelScore*> by_rank;
  for (const auto& m : r.models) by_rank.push_back(&m);
  std::stable_sort(by_rank.begin(), by_rank.end(),
                   [](const ModelScore* a, const ModelScore* b) { return a->rank < b->rank; });
  return by_rank[0]->score - by_rank[1]->score;
}

std::string serialize_match_result(const MatchResult& r) {
  Json models = Json::array();
  for (const auto& m : r.models) {
    Json pairs = Json::array();
    for (const auto& p : m.pairs) {
      Json pj{{"object_segment", p.object_segment},
              {"model_segment", nullptr},
              {"unary_error", finite(p.unary_error, "unary_error")}};
      if (p.model_segment >= 0) pj["model_segment"] = p.model_segment;
      pairs.push_back(pj);
    }
    models.push_back(Json{{"model", m.model},
                          {"score", finite(m.score, "score")},
                          {"rank", m.rank},
                          {"error_unary", finite(m.error_unary, "error_unary")},
                          {"error_orientation", finite(m.error_orientation, "error_orientation")},
                          {"error_distance", finite(m.error_distance, "error_distance")},
                          {"error_coverage", finite(m.error_coverage, "error_coverage")},
                          {"error_total", finite(m.error_total, "error_total")},
                          {"pairs", pairs}});
  }
  const double margin = match_margin(r);
  Json j{{"format", kMatchFormat},
         {"version", kVersion},
         {"provenance", provenance_json(r.provenance)},
         {"object", r.object},
         {"error_form", r.error_form},
         {"entropy", finite(r.entropy, "entropy")},
         {"margin", std::isnan(margin) ? Json(nullptr) : Json(finite(margin, "margin"))},
         {"models", models}};
  return dump(j);
}

MatchResult parse_match_result(const std::string& text, const std::string& name) {
  const Json j = open_json_document(text, name, kMatchFormat);
  MatchResult r;
  try {
    r.provenance = provenance_from(j.at("provenance"));
    r.object = string_at(j, "object", "");
    r.error_form = string_at(j, "error_form", "");
    r.entropy = double_at(j, "entropy", "");
    const Json& models = array_at(j, "models", "");
    for (std::size_t k = 0; k < models.size(); ++k) {
      const Json& m = models[k];
      const std::string w = "models[" + std::to_string(k) + "].";
      if (!m.is_object()) throw Malformed(w.substr(0, w.size() - 1) + " must be an object");
      ModelScore s;
      s.model = string_at(m, "model", w);
      s.score = double_at(m, "score", w);
      s.rank = int_at(m, "rank", w, 1);
      s.error_unary = double_at(m, "error_unary", w);
      s.error_orientation = double_at(m, "error_orientation", w);
      s.error_distance = double_at(m, "error_distance", w);
      s.error_coverage = double_at(m, "error_coverage", w);
      s.error_total = double_at(m, "error_total", w);
      const Json& pairs = array_at(m, "pairs", w);
      for (std::size_t q = 0; q < pairs.size(); ++q) {
        const Json& p = pairs[q];
        const std::string pw = w + "pairs[" + std::to_string(q) + "].";
        if (!p.is_object()) throw Malformed(pw.substr(0, pw.size() - 1) + " must be an object");
        SegmentPair sp;
        sp.object_segment = int_at(p, "object_segment", pw, 0);
        sp.model_segment = p.at("model_segment").is_null() ? -1 : int_at(p, "model_segment", pw, 0);
        sp.unary_error = double_at(p, "unary_error", pw);
        s.pairs.push_back(sp);
      }
      r.models.push_back(std::move(s));
    }
    // "margin" is derived from the scores (match_margin); files before it was added lack it.
    if (j.contains("margin") && !j["margin"].is_null()) double_at(j, "margin", "");
  } catch (const DataError&) { throw; } catch (const Malformed& e) {
    throw DataError(name, std::string("malformed match result: ") + e.what());
  } catch (const std::exception& e) {
    throw DataError(name, "malformed match result: " + detail::quote(library_text(e), 200));
  }
  return r;
}

MatchResult read_match_result(const std::string& path) {
  return parse_match_result(common::read_file(path), path);
}

void write_match_result(const MatchResult& result, const std::string& path) {
  common::write_file_atomic(path, serialize_match_result(result));
}

Json open_json_document(const std::string& text, const std::string& name, const char* format,
                        const Json::parser_callback_t& filter, int max_version) {
  // canopy documents nest 5 levels; nlohmann copies values recursively (ordered_json's
  // objects copy their values when they grow), so a 60 KB file of nested brackets would
  // overflow the stack. Refuse deep nesting before parsing.
  constexpr int kMaxDepth = 64;
  int depth = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxDepth) {
        throw DataError(
            name, "JSON nested deeper than " + std::to_string(kMaxDepth) + " levels (not a canopy document)");
      }
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  Json j;
  try {
    j = filter ? Json::parse(text, filter) : Json::parse(text);
  } catch (const Json::exception& e) {  // parse errors, and numbers out of double's range (1e400)
    const std::string is = detail::sniff(text);
    if (!is.empty() && is != "a JSON document")
      throw DataError(name, "this is " + is + ", not a JSON document");
    throw DataError(name, "not valid JSON: " + detail::quote(library_text(e), 200));
  }
  if (!j.is_object() || !j.contains("format"))
    throw DataError(name, "no \"format\" key (not a canopy JSON document)");
  if (!j["format"].is_string() || j["format"].get<std::string>() != format) {
    throw DataError(name, "format is " + describe(j["format"]) + ", expected \"" + format + "\"");
  }
  if (!j.contains("version") || !(j["version"].is_number_integer() || j["version"].is_number_unsigned())) {
    throw DataError(name, "no integer \"version\"");
  }
  const Json& v = j["version"];
  const bool known =
      v.is_number_unsigned()
          ? v.get<std::uint64_t>() >= static_cast<std::uint64_t>(kVersion) &&
                v.get<std::uint64_t>() <= static_cast<std::uint64_t>(std::max(max_version, kVersion))
          : v.get<std::int64_t>() >= kVersion && v.get<std::int64_t>() <= std::max(max_version, kVersion);
  if (!known) {
    throw DataError(
        name, std::string(format) + " version " + v.dump() + " is not supported (this build reads " +
                  (max_version > kVersion ? "versions 1-" + std::to_string(max_version) : "version 1") + ")");
  }
  return j;
}

}  // namespace canopy::formats
