#include "canopy/documents/scene_score.h"

#include <cstdio>
#include <limits>
#include <map>
#include <set>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/formats/json_document.h"
#include "members.h"

namespace canopy::documents {
namespace {

using namespace members;  // NOLINT(google-build-using-namespace): the document's member helpers

const char* const kTables[] = {"summary", "pr", "models", "cover_bins", "reliability", "clutter"};

// --- writing: the document built as score built it, member by member, so the library's number
// text (3 as "3", 3.0 as "3.0") and key order are the ones score has always written.

Json value_json(const ScoreValue& v) {
  switch (v.kind) {
    case ScoreValue::Kind::integer: return Json(v.integer);
    case ScoreValue::Kind::number: return Json(v.number);
    case ScoreValue::Kind::text: return Json(v.text);
    case ScoreValue::Kind::null: break;
  }
  return Json(nullptr);
}

template <class T>
Json or_null(const std::optional<T>& v) {
  return v ? Json(*v) : Json(nullptr);
}

template <class T>
const T& need(const std::optional<T>& v, const char* what) {
  if (!v) throw common::Error(std::string("score: refusing to write a tile without ") + what);
  return *v;
}

Json rows_json(const std::vector<ScoreRow>& rows) {
  Json out = Json::array();
  for (const ScoreRow& r : rows) {
    Json j = Json::object();
    for (const auto& [k, v] : r) j[k] = value_json(v);
    out.push_back(std::move(j));
  }
  return out;
}

Json tile_json(const ScoreTile& t) {
  return Json{{"detections", t.detections},
              {"truth", t.truth},
              {"cover", or_null(t.cover)},
              {"noise_mm", or_null(t.noise_mm)},
              {"area_ha", need(t.area_ha, "area_ha")},
              {"true", need(t.true_count, "true")},
              {"tp", need(t.tp, "tp")},
              {"fp", need(t.fp, "fp")},
              {"fn", need(t.fn, "fn")},
              {"class_detections", need(t.class_detections, "class_detections")},
              {"class_tp", need(t.class_tp, "class_tp")},
              {"class_fp", need(t.class_fp, "class_fp")},
              {"fn_any_level", need(t.fn_any_level, "fn_any_level")}};
}

Json match_json(const ScoreMatch& m) {
  return Json{{"tile", m.tile},
              {"candidate", or_null(m.candidate)},
              {"level", or_null(m.level)},
              {"model", or_null(m.model)},
              {"class", or_null(m.cls)},
              {"confidence", or_null(m.confidence)},
              {"x", or_null(m.x)},
              {"y", or_null(m.y)},
              {"heading", or_null(m.heading)},
              {"outcome", m.outcome},
              {"instance", or_null(m.instance)},
              {"true_model", or_null(m.true_model)},
              {"cover", or_null(m.cover)},
              {"distance_m", or_null(m.distance_m)},
              {"heading_error_deg", or_null(m.heading_error_deg)},
              {"fate", or_null(m.fate)},
              {"fate_candidate", or_null(m.fate_candidate)},
              {"fate_reason", or_null(m.fate_reason)},
              {"fate_density", or_null(m.fate_density)}};
}

Json table_json(const SceneScore& s, const std::string& table) {
  if (table == "summary") return rows_json(s.summary);
  if (table == "pr") return rows_json(s.pr);
  if (table == "models") return rows_json(s.models);
  if (table == "cover_bins") return rows_json(s.cover_bins);
  if (table == "reliability") return rows_json(s.reliability);
  if (table == "clutter") return rows_json(s.clutter);
  if (table == "matches") {
    Json out = Json::array();
    for (const ScoreMatch& m : s.matches) out.push_back(match_json(m));
    return out;
  }
  throw common::Error("score: no table \"" + table + "\"");
}

// --- reading

std::optional<std::string> optional_text(const Json& j, const char* key, const std::string& w) {
  const Json* v = optional(j, key);
  if (!v) return std::nullopt;
  return text(*v, path(w, key));
}

std::optional<double> optional_number(const Json& j, const char* key, const std::string& w) {
  const Json* v = optional(j, key);
  if (!v) return std::nullopt;
  return finite_number(*v, path(w, key));
}

std::optional<std::int64_t> optional_count(const Json& j, const char* key, const std::string& w) {
  const Json* v = optional(j, key);
  if (!v) return std::nullopt;
  return count(*v, path(w, key));
}

ScoreParams params_of(const Json& p) {
  object(p, "params");
  ScoreParams out;
  out.match_radius_m = optional_number(p, "match_radius_m", "params");
  if (out.match_radius_m && !(*out.match_radius_m > 0)) throw Malformed("params.match_radius_m must be > 0");
  if (const Json* b = optional(p, "cover_bins")) {
    array(*b, "params.cover_bins");
    for (std::size_t i = 0; i < b->size(); ++i)
      out.cover_bins.push_back(finite_number((*b)[i], "params.cover_bins[" + std::to_string(i) + "]"));
  }
  out.flip_threshold_deg = optional_number(p, "flip_threshold_deg", "params");
  return out;
}

ScoreTile tile_of(const Json& t, const std::string& w) {
  object(t, w);
  ScoreTile out;
  out.detections = optional_text(t, "detections", w).value_or("");
  out.truth = optional_text(t, "truth", w).value_or("");
  out.cover = optional_text(t, "cover", w);
  out.noise_mm = optional_number(t, "noise_mm", w);
  out.area_ha = optional_number(t, "area_ha", w);
  if (out.area_ha && *out.area_ha < 0) throw Malformed(w + ".area_ha must be >= 0");
  out.true_count = optional_count(t, "true", w);
  out.tp = optional_count(t, "tp", w);
  out.fp = optional_count(t, "fp", w);
  out.fn = optional_count(t, "fn", w);
  out.class_detections = optional_count(t, "class_detections", w);
  out.class_tp = optional_count(t, "class_tp", w);
  out.class_fp = optional_count(t, "class_fp", w);
  out.fn_any_level = optional_count(t, "fn_any_level", w);
  return out;
}

ScoreRow row_of(const Json& r, const std::string& w) {
  object(r, w);
  ScoreRow out;
  for (const auto& [k, v] : r.items()) {
    const std::string what = w + "." + k;
    if (v.is_null()) {
      out.emplace_back(k, ScoreValue());
    } else if (v.is_number_unsigned()) {
      if (v.get<std::uint64_t>() > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
        throw Malformed(what + " is beyond the integers read, " + describe(v));
      out.emplace_back(k, ScoreValue(v.get<std::int64_t>()));
    } else if (v.is_number_integer()) {
      out.emplace_back(k, ScoreValue(v.get<std::int64_t>()));
    } else if (v.is_number()) {
      out.emplace_back(k, ScoreValue(v.get<double>()));
    } else if (v.is_string()) {
      out.emplace_back(k, ScoreValue(v.get<std::string>()));
    } else {
      throw Malformed(what + " must be a number, a text or null, not " + describe(v));
    }
  }
  return out;
}

ScoreMatch match_of(const Json& m, const std::string& w, std::size_t tiles) {
  if (!m.is_object()) throw Malformed(w + " must be an object, not " + describe(m));
  ScoreMatch out;
  out.tile = count(at(m, "tile", w), w + ".tile");
  if (out.tile >= static_cast<std::int64_t>(tiles)) {
    throw Malformed(w + ".tile " + std::to_string(out.tile) + " is not one of the " + std::to_string(tiles) +
                    " tiles");
  }
  out.outcome = text(at(m, "outcome", w), w + ".outcome");
  if (out.outcome != "right" && out.outcome != "wrong" && out.outcome != "false_alarm" &&
      out.outcome != "missed")
    throw Malformed(w + ".outcome must be right, wrong, false_alarm or missed, not " +
                    describe(at(m, "outcome", w)));
  out.candidate = optional_text(m, "candidate", w);
  out.level = optional_text(m, "level", w);
  out.model = optional_text(m, "model", w);
  out.cls = optional_text(m, "class", w);
  out.confidence = optional_number(m, "confidence", w);
  out.x = optional_number(m, "x", w);
  out.y = optional_number(m, "y", w);
  out.heading = optional_number(m, "heading", w);
  out.instance = optional_count(m, "instance", w);
  out.true_model = optional_text(m, "true_model", w);
  out.cover = optional_number(m, "cover", w);
  out.distance_m = optional_number(m, "distance_m", w);
  out.heading_error_deg = optional_number(m, "heading_error_deg", w);
  out.fate = optional_text(m, "fate", w);
  out.fate_candidate = optional_text(m, "fate_candidate", w);
  out.fate_reason = optional_text(m, "fate_reason", w);
  out.fate_density = optional_number(m, "fate_density", w);
  if (out.fate) {
    if (out.outcome != "missed") throw Malformed(w + ": a \"fate\" on a row that is not missed");
    if (*out.fate != "no_candidate" && *out.fate != "refused" && *out.fate != "taken" &&
        *out.fate != "off_centre")
      throw Malformed(w + ".fate must be no_candidate, refused, taken or off_centre, not \"" + *out.fate +
                      "\"");
  }
  if (out.outcome != "missed" && !out.candidate) throw Malformed(w + ": missing \"candidate\"");
  if (out.outcome != "false_alarm" && !out.instance) throw Malformed(w + ": missing \"instance\"");
  return out;
}

SceneScore read_members(const Json& j) {
  SceneScore s;
  if (const Json* prov = optional(j, "provenance"); prov && prov->is_object()) {
    if (const Json* p = optional(*prov, "parameters"); p && p->is_object()) {
      for (const auto& [k, v] : p->items()) {
        if (v.is_string()) s.parameters.emplace_back(k, v.get<std::string>());
      }
    }
  }
  if (const Json* p = optional(j, "params")) {
    s.params = params_of(*p);
    s.has_params = true;
  }
  const Json& tiles = array(at(j, "tiles", "score"), "score.tiles");
  for (std::size_t i = 0; i < tiles.size(); ++i)
    s.tiles.push_back(tile_of(tiles[i], "tiles[" + std::to_string(i) + "]"));
  std::vector<ScoreRow>* const into[] = {&s.summary,    &s.pr,          &s.models,
                                         &s.cover_bins, &s.reliability, &s.clutter};
  for (std::size_t t = 0; t < 6; ++t) {
    const Json* rows = optional(j, kTables[t]);
    if (!rows) continue;
    array(*rows, std::string("score.") + kTables[t]);
    for (std::size_t i = 0; i < rows->size(); ++i)
      into[t]->push_back(row_of((*rows)[i], std::string(kTables[t]) + "[" + std::to_string(i) + "]"));
  }
  const Json& matches = array(at(j, "matches", "score"), "score.matches");
  std::set<std::pair<std::int64_t, std::string>> seen;
  for (std::size_t i = 0; i < matches.size(); ++i) {
    const std::string w = "matches[" + std::to_string(i) + "]";
    s.matches.push_back(match_of(matches[i], w, tiles.size()));
    const ScoreMatch& m = s.matches.back();
    if (m.outcome != "missed" && !seen.emplace(m.tile, *m.candidate).second) {
      throw Malformed(w + ".candidate \"" + *m.candidate + "\" has a second outcome in tile " +
                      std::to_string(m.tile));
    }
  }
  return s;
}

}  // namespace

const ScoreValue* score_cell(const ScoreRow& row, const std::string& key) {
  for (const auto& [k, v] : row) {
    if (k == key) return &v;
  }
  return nullptr;
}

std::string write_scene_score(const SceneScore& s, const formats::Provenance& provenance) {
  Json tiles = Json::array();
  for (const ScoreTile& t : s.tiles) tiles.push_back(tile_json(t));
  const ScoreParams& p = s.params;
  if (!s.has_params || !p.match_radius_m || !p.flip_threshold_deg)
    throw common::Error("score: refusing to write a score without its params");
  const Json doc{{"format", kSceneScoreFormat},
                 {"version", kSceneScoreVersion},
                 {"provenance", formats::provenance_json(provenance)},
                 {"params", Json{{"match_radius_m", *p.match_radius_m},
                                 {"cover_bins", p.cover_bins},
                                 {"flip_threshold_deg", *p.flip_threshold_deg}}},
                 {"tiles", tiles},
                 {"summary", table_json(s, "summary")},
                 {"pr", table_json(s, "pr")},
                 {"models", table_json(s, "models")},
                 {"cover_bins", table_json(s, "cover_bins")},
                 {"reliability", table_json(s, "reliability")},
                 {"clutter", table_json(s, "clutter")},
                 {"matches", table_json(s, "matches")}};
  return doc.dump(1) + "\n";
}

std::string scene_score_csv(const SceneScore& s, const std::string& table) {
  const Json rows = table_json(s, table);
  std::string out;
  if (rows.empty()) return out;
  std::vector<std::string> columns;
  for (const auto& [k, v] : rows[0].items()) columns.push_back(k);
  for (std::size_t c = 0; c < columns.size(); ++c) out += (c ? "," : "") + columns[c];
  out += "\n";
  for (const Json& r : rows) {
    for (std::size_t c = 0; c < columns.size(); ++c) {
      if (c) out += ",";
      const Json& v = r.contains(columns[c]) ? r[columns[c]] : Json(nullptr);
      if (v.is_null()) continue;
      if (v.is_string()) {
        std::string x = v.get<std::string>();
        if (x.find_first_of(",\"\n") != std::string::npos) {
          std::string q = "\"";
          for (char ch : x) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
          x = q + "\"";
        }
        out += x;
      } else if (v.is_number_float()) {
        char buf[40];
        std::snprintf(buf, sizeof buf, "%.10g", v.get<double>());
        out += buf;
      } else {
        out += v.dump();
      }
    }
    out += "\n";
  }
  return out;
}

SceneScore read_scene_score(const std::string& text, const std::string& name) {
  const Json j = formats::open_json_document(text, name, kSceneScoreFormat, nullptr, kSceneScoreVersion);
  try {
    return read_members(j);
  } catch (const Malformed& e) { throw common::DataError(name, e.what()); }
}

SceneScore read_scene_score_file(const std::string& path) {
  return read_scene_score(common::read_file(path), path);
}

}  // namespace canopy::documents
