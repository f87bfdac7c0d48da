#include "canopy/documents/match_result.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/formats/json_document.h"
#include "canopy/formats/json_fields.h"
#include "members.h"

namespace canopy::documents {
namespace {

using formats::finite_for_writing;
using members::Json;

}  // namespace

double match_margin(const MatchResult& r) {
  if (r.models.size() < 2) return std::numeric_limits<double>::quiet_NaN();
  std::vector<const ModelScore*> by_rank;
  for (const auto& m : r.models) by_rank.push_back(&m);
  std::stable_sort(by_rank.begin(), by_rank.end(),
                   [](const ModelScore* a, const ModelScore* b) { return a->rank < b->rank; });
  return by_rank[0]->score - by_rank[1]->score;
}

double match_entropy(const std::vector<double>& scores) {
  if (scores.empty()) return 0;
  double total = 0;
  for (double s : scores) total += std::max(0.0, s);
  if (!(total > 0)) return std::log2(static_cast<double>(scores.size()));
  double h = 0;
  for (double s : scores) {
    const double q = std::max(0.0, s) / total;
    if (q > 0) h -= q * std::log2(q);
  }
  return std::max(0.0, h);
}

std::string serialize_match_result(const MatchResult& r) {
  Json models = Json::array();
  for (std::size_t k = 0; k < r.models.size(); ++k) {
    const ModelScore& m = r.models[k];
    Json pairs = Json::array();
    for (const auto& p : m.pairs) {
      Json pj{{"object_segment", p.object_segment},
              {"model_segment", nullptr},
              {"unary_error", finite_for_writing(p.unary_error, "unary_error")}};
      if (p.model_segment >= 0) pj["model_segment"] = p.model_segment;
      pairs.push_back(pj);
    }
    Json entry{{"model", m.model},
               {"score", finite_for_writing(m.score, "score")},
               {"rank", m.rank},
               {"error_unary", finite_for_writing(m.error_unary, "error_unary")},
               {"error_orientation", finite_for_writing(m.error_orientation, "error_orientation")},
               {"error_distance", finite_for_writing(m.error_distance, "error_distance")},
               {"error_coverage", finite_for_writing(m.error_coverage, "error_coverage")},
               {"error_total", finite_for_writing(m.error_total, "error_total")},
               {"pairs", pairs}};
    // Only when set: gmatch's files stay byte-identical to those written before the key existed.
    if (m.pose) {
      Json pose = Json::array();
      for (const double v : *m.pose) pose.push_back(finite_for_writing(v, "pose"));
      try {
        members::check_rigid(*m.pose, "models[" + std::to_string(k) + "].pose");
      } catch (const std::exception& e) {
        throw common::Error(std::string("match result: refusing to write ") + e.what());
      }
      entry["pose"] = pose;
    }
    models.push_back(entry);
  }
  const double margin = match_margin(r);
  Json j{{"format", kMatchResultFormat},
         {"version", kMatchResultVersion},
         {"provenance", formats::provenance_json(r.provenance)},
         {"object", r.object},
         {"error_form", r.error_form},
         {"entropy", finite_for_writing(r.entropy, "entropy")},
         {"margin", std::isnan(margin) ? Json(nullptr) : Json(finite_for_writing(margin, "margin"))},
         {"models", models}};
  return formats::json_document_text(j);
}

MatchResult parse_match_result(const std::string& text, const std::string& name) {
  const Json j = formats::open_json_document(text, name, kMatchResultFormat);
  MatchResult r;
  try {
    r.provenance = formats::json_provenance(j.at("provenance"));
    r.object = formats::json_string_at(j, "object", "");
    r.error_form = formats::json_string_at(j, "error_form", "");
    r.entropy = formats::json_number_at(j, "entropy", "");
    const Json& models = formats::json_array_at(j, "models", "");
    for (std::size_t k = 0; k < models.size(); ++k) {
      const std::string w = members::item("", "models", k);
      const Json& m = members::item_object(models[k], w);
      ModelScore s;
      s.model = formats::json_string_at(m, "model", w);
      s.score = formats::json_number_at(m, "score", w);
      s.rank = formats::json_int_at(m, "rank", w, 1);
      s.error_unary = formats::json_number_at(m, "error_unary", w);
      s.error_orientation = formats::json_number_at(m, "error_orientation", w);
      s.error_distance = formats::json_number_at(m, "error_distance", w);
      s.error_coverage = formats::json_number_at(m, "error_coverage", w);
      s.error_total = formats::json_number_at(m, "error_total", w);
      const Json& pairs = formats::json_array_at(m, "pairs", w);
      for (std::size_t q = 0; q < pairs.size(); ++q) {
        const std::string pw = members::item(w, "pairs", q);
        const Json& p = members::item_object(pairs[q], pw);
        SegmentPair sp;
        sp.object_segment = formats::json_int_at(p, "object_segment", pw, 0);
        sp.model_segment =
            p.at("model_segment").is_null() ? -1 : formats::json_int_at(p, "model_segment", pw, 0);
        sp.unary_error = formats::json_number_at(p, "unary_error", pw);
        s.pairs.push_back(sp);
      }
      // Optional (baseline --hypotheses); files without it are gmatch's and those before it.
      if (m.contains("pose") && !m.at("pose").is_null())
        s.pose = members::rigid_matrix(m.at("pose"), w + "pose");
      r.models.push_back(std::move(s));
    }
    // "margin" is derived from the scores (match_margin); files before it was added lack it.
    if (j.contains("margin") && !j["margin"].is_null()) formats::json_number_at(j, "margin", "");
  } catch (...) { members::rethrow_malformed(name, "match result"); }
  return r;
}

MatchResult read_match_result(const std::string& path) {
  return parse_match_result(common::read_file(path), path);
}

void write_match_result(const MatchResult& result, const std::string& path) {
  common::write_file_atomic(path, serialize_match_result(result));
}

}  // namespace canopy::documents
