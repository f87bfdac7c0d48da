#include "canopy/formats/json_io.h"

#include <cmath>
#include <nlohmann/json.hpp>

#include "canopy/common/atomic_file.h"
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

Json provenance_json(const Provenance& p) {
  Json params = Json::object();
  for (const auto& [k, v] : p.parameters) params[k] = v;
  return Json{{"tool", p.tool}, {"version", p.version}, {"parameters", params}, {"inputs", p.inputs}};
}

Provenance provenance_from(const Json& j) {
  Provenance p;
  p.tool = j.at("tool").get<std::string>();
  p.version = j.at("version").get<std::string>();
  for (const auto& [k, v] : j.at("parameters").items()) p.parameters.emplace_back(k, v.get<std::string>());
  p.inputs = j.at("inputs").get<std::vector<std::string>>();
  return p;
}

Vec3 vec3_from(const Json& j) {
  if (!j.is_array() || j.size() != 3) throw std::invalid_argument("expected an array of 3 numbers");
  return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

// Parses the document and checks "format" and "version".
Json open_document(const std::string& text, const std::string& name, const char* format) {
  Json j;
  try {
    j = Json::parse(text);
  } catch (const Json::parse_error& e) {
    throw DataError(name, std::string("not valid JSON: ") + e.what());
  }
  if (!j.is_object() || !j.contains("format")) throw DataError(name, "no \"format\" key (not a canopy JSON document)");
  if (!j["format"].is_string() || j["format"].get<std::string>() != format) {
    throw DataError(name, "format is " + j["format"].dump() + ", expected \"" + format + "\"");
  }
  if (!j.contains("version") || !j["version"].is_number_integer()) throw DataError(name, "no integer \"version\"");
  if (j["version"].get<int>() != kVersion) {
    throw DataError(name, std::string(format) + " version " + j["version"].dump() + " is not supported (this build reads version 1)");
  }
  return j;
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
  for (const auto& e : g.adjacency) adj.push_back(Json{{"a", e.a}, {"b", e.b}, {"shared_edges", e.shared_edges}});
  Json j{{"format", kGraphFormat}, {"version", kVersion}, {"provenance", provenance_json(g.provenance)},
         {"mesh", g.mesh}, {"segments", segs}, {"adjacency", adj}};
  return dump(j);
}

SegmentGraph parse_segment_graph(const std::string& text, const std::string& name) {
  const Json j = open_document(text, name, kGraphFormat);
  SegmentGraph g;
  try {
    g.provenance = provenance_from(j.at("provenance"));
    g.mesh = j.at("mesh").get<std::string>();
    for (const auto& s : j.at("segments")) {
      Segment seg;
      seg.segment_id = s.at("segment_id").get<int>();
      seg.vertex_count = s.at("vertex_count").get<int>();
      seg.area = s.at("area").get<double>();
      seg.radii = vec3_from(s.at("radii"));
      seg.thickness = s.at("thickness").get<double>();
      seg.elongation = s.at("elongation").get<double>();
      seg.centroid = vec3_from(s.at("centroid"));
      seg.normal = vec3_from(s.at("normal"));
      seg.label = s.at("label").get<int>();
      seg.label_purity = s.at("label_purity").get<double>();
      seg.vertices = s.at("vertices").get<std::vector<int>>();
      g.segments.push_back(std::move(seg));
    }
    for (const auto& e : j.at("adjacency")) {
      g.adjacency.push_back({e.at("a").get<int>(), e.at("b").get<int>(), e.at("shared_edges").get<int>()});
    }
  } catch (const DataError&) {
    throw;
  } catch (const std::exception& e) {
    throw DataError(name, std::string("malformed segment graph: ") + e.what());
  }
  return g;
}

SegmentGraph read_segment_graph(const std::string& path) {
  return parse_segment_graph(common::read_file(path), path);
}

void write_segment_graph(const SegmentGraph& graph, const std::string& path) {
  common::write_file_atomic(path, serialize_segment_graph(graph));
}

std::string serialize_match_result(const MatchResult& r) {
  Json models = Json::array();
  for (const auto& m : r.models) {
    Json pairs = Json::array();
    for (const auto& p : m.pairs) {
      Json pj{{"object_segment", p.object_segment}, {"model_segment", nullptr},
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
  Json j{{"format", kMatchFormat}, {"version", kVersion}, {"provenance", provenance_json(r.provenance)},
         {"object", r.object}, {"error_form", r.error_form}, {"entropy", finite(r.entropy, "entropy")},
         {"models", models}};
  return dump(j);
}

MatchResult parse_match_result(const std::string& text, const std::string& name) {
  const Json j = open_document(text, name, kMatchFormat);
  MatchResult r;
  try {
    r.provenance = provenance_from(j.at("provenance"));
    r.object = j.at("object").get<std::string>();
    r.error_form = j.at("error_form").get<std::string>();
    r.entropy = j.at("entropy").get<double>();
    for (const auto& m : j.at("models")) {
      ModelScore s;
      s.model = m.at("model").get<std::string>();
      s.score = m.at("score").get<double>();
      s.rank = m.at("rank").get<int>();
      s.error_unary = m.at("error_unary").get<double>();
      s.error_orientation = m.at("error_orientation").get<double>();
      s.error_distance = m.at("error_distance").get<double>();
      s.error_coverage = m.at("error_coverage").get<double>();
      s.error_total = m.at("error_total").get<double>();
      for (const auto& p : m.at("pairs")) {
        SegmentPair sp;
        sp.object_segment = p.at("object_segment").get<int>();
        sp.model_segment = p.at("model_segment").is_null() ? -1 : p.at("model_segment").get<int>();
        sp.unary_error = p.at("unary_error").get<double>();
        s.pairs.push_back(sp);
      }
      r.models.push_back(std::move(s));
    }
  } catch (const DataError&) {
    throw;
  } catch (const std::exception& e) {
    throw DataError(name, std::string("malformed match result: ") + e.what());
  }
  return r;
}

MatchResult read_match_result(const std::string& path) {
  return parse_match_result(common::read_file(path), path);
}

void write_match_result(const MatchResult& result, const std::string& path) {
  common::write_file_atomic(path, serialize_match_result(result));
}

}  // namespace canopy::formats
