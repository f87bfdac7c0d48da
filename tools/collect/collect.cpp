#include "collect/collect.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>
#include <cstdio>
#include <filesystem>
#include <regex>
#include <stdexcept>

#include "canopy/common/atomic_file.h"
#include "canopy/common/density_scale.h"
#include "canopy/common/error.h"
#include "canopy/common/math.h"
#include "canopy/common/vehicle_classes.h"
#include "canopy/documents/candidates.h"
#include "canopy/documents/detections.h"
#include "canopy/formats/ini.h"
#include "canopy/formats/las_crs.h"
#include "canopy/formats/provenance.h"
#include "canopy/documents/stage_outcome.h"
#include "collect/messages.h"

namespace canopy::collect {
namespace {

Corner apply(const Matrix& m, double x, double y) {
  return {m[0] * x + m[1] * y + m[3], m[4] * x + m[5] * y + m[7]};
}

}  // namespace

Matrix multiply(const Matrix& a, const Matrix& b) {
  Matrix p{};
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += a[4 * r + k] * b[4 * k + c];
      p[4 * r + c] = s;
    }
  }
  return p;
}

std::array<double, 3> euler_degrees(const Matrix& m) {
  const double deg = 180 / common::kPi;
  const double heading = std::atan2(m[4], m[0]);
  const double pitch = std::asin(std::max(-1.0, std::min(1.0, -m[8])));
  const double roll = std::atan2(m[9], m[10]);
  return {heading * deg, pitch * deg, roll * deg};
}

Index parse_index(const std::string& text, const std::string& name) {
  const documents::Candidates doc = documents::read_candidates(text, name);
  Index index;
  index.name = name;
  index.tile = doc.tile;
  index.crs = doc.crs;
  index.crs_from = doc.crs_from;
  for (const documents::Candidate& d : doc.candidates) {
    index.candidates.push_back(Candidate{d.id, d.transform, d.length, d.width, d.object_density()});
  }
  index.density = doc.density;
  index.warnings = doc.warnings;
  return index;
}

Verdict absent_verdict(const std::string& name) {
  Verdict v;
  v.name = name;
  v.present = false;
  return v;
}

namespace {

// A pose of the verdict as a 4 x 4 row-major matrix (last row 0 0 0 1).
Matrix matrix_of(const formats::Pose& p) {
  Matrix m{};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m[4 * r + c] = p.rotation[3 * r + c];
    m[4 * r + 3] = p.translation[r];
  }
  m[15] = 1;
  return m;
}

}  // namespace

Verdict from_stage_verdict(const documents::StageVerdict& s, const std::string& name) {
  Verdict v;
  v.name = name;
  v.present = s.outcome != documents::StageOutcome::missing;
  v.failed = s.outcome == documents::StageOutcome::failed;
  if (s.outcome != documents::StageOutcome::written) return v;
  const documents::Verdict& d = s.verdict;
  v.candidate = d.candidate;
  v.level = d.level;
  v.model = d.model;
  v.cls = d.vehicle_class;
  v.group = d.group;
  v.confidence = d.confidence;
  if (d.pose) v.pose = matrix_of(*d.pose);
  if (d.pose_tile) v.pose_tile = matrix_of(*d.pose_tile);
  v.reason = d.reason;
  v.detail = d.detail;
  v.refused_on = d.refused_on;
  v.density = d.density;
  v.density_class = d.density_class;
  v.density_model = d.density_model;
  v.size = d.size;
  v.heading_ambiguity = d.heading_ambiguity;
  v.measured_size = d.measured_size;
  v.measured_centre = d.measured_centre;
  v.measured_heading = d.measured_heading;
  v.measured_edge_correction = d.measured_edge_correction;
  return v;
}

Verdict parse_verdict(const std::string& text, const std::string& name) {
  return from_stage_verdict(documents::parse_stage_verdict(text, name), name);
}

Verdict read_verdict(const std::string& path) {
  Verdict v = from_stage_verdict(documents::read_stage_verdict(path), path);
  if (v.failed) v.failed_log = failed_stage_log(path);
  return v;
}

std::string failed_stage_log(const std::string& verdict) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(verdict).parent_path();
  auto empty_file = [](const fs::path& p) {
    std::error_code ec;
    return fs::is_regular_file(p, ec) && fs::file_size(p, ec) == 0 && !ec;
  };
  for (const char* artifact : kModelChainArtifacts) {
    const fs::path p = dir / artifact;
    if (empty_file(p)) return p.string() + ".log";
  }
  return verdict + ".log";
}

bool names_candidate(const std::string& points, const std::string& id) {
  const std::filesystem::path p(points);
  return p.stem() == id || p.parent_path().filename() == id;
}

void check_verdict_of(const Verdict& v, const std::string& id, const std::string& index_dir) {
  if (v.failed || !v.present) return;
  if (!names_candidate(v.candidate, id)) {
    throw common::DataError(v.name, "was written for \"" + v.candidate + "\", not for candidate " + id +
                                        " (its points are " + id + ".pcd or " + id + "/<file>)");
  }
  // When the points are there to look at, they must be this tile's: detect's <id>.pcd beside
  // the index, or a file in the candidate's directory (beside the index or the verdict).
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path points(v.candidate);
  if (!fs::exists(points, ec)) return;
  const fs::path dir = points.parent_path().empty() ? fs::path(".") : points.parent_path();
  const fs::path index = index_dir.empty() ? fs::path(".") : fs::path(index_dir);
  const fs::path verdict_dir =
      fs::path(v.name).parent_path().empty() ? fs::path(".") : fs::path(v.name).parent_path();
  auto same = [&](const fs::path& a, const fs::path& b) {
    std::error_code e;
    return fs::equivalent(a, b, e) && !e;
  };
  if ((points.stem() == id && same(dir, index)) || same(dir, index / id) || same(dir, verdict_dir)) return;
  // A copy of a tile's directory (cp -a OUT1 OUT2; stop 71) keeps the verdicts the original's
  // tools wrote, which name the original's points: a file with the same bytes at that place of
  // this tile is this candidate's points (verify takes a copied segment graph so too).
  std::vector<fs::path> here{index / id / points.filename(), verdict_dir / points.filename()};
  if (points.stem() == id) here.push_back(index / points.filename());
  for (const fs::path& p : here) {
    std::error_code e;
    if (fs::is_regular_file(p, e) && common::same_file_contents(p.string(), points.string())) return;
  }
  throw common::DataError(v.name, "was written for " + v.candidate + ", which is not candidate " + id +
                                      " of this tile (not " + (index / (id + ".pcd")).string() + " nor in " +
                                      (index / id).string() + "/ or " + verdict_dir.string() + "/)");
}

std::string plan(const Index& index, const std::string& key, double model_density, bool scale) {
  std::string out =
      "# generated by collect --plan from " + index.name + "; read by mk/scenes.mk\n" + key + "_CANDS :=";
  for (const auto& c : index.candidates) out += " " + c.id;
  out += "\n";
  for (const auto& c : index.candidates) {
    out += key + "_TRANSFORM_" + c.id + " :=";
    for (int i = 0; i < 16; ++i) {
      char buf[40];
      std::snprintf(buf, sizeof buf, "%s%.17g", i ? "," : " ", c.transform[i]);
      out += buf;
    }
    out += "\n";
  }
  for (const auto& c : index.candidates) {
    const bool model = !c.density || *c.density >= model_density;
    out += key + "_LEVEL_" + c.id + " := " + (model ? "model" : "class") + "\n";
  }
  // The density rule's options of the model-level candidates below the dense end (none at or
  // above it, nor for an unknown density: today's command lines).
  if (!scale) return out;
  for (const auto& c : index.candidates) {
    if (!c.density || *c.density < model_density) continue;
    const common::DensityScale s = common::density_scale(*c.density);
    if (s.dense_end()) continue;
    for (const char* stage : common::kDensityScaledStages) {
      std::string name = stage;
      std::transform(name.begin(), name.end(), name.begin(), [](unsigned char ch) { return std::toupper(ch); });
      out += key + "_" + name + "_" + c.id + " := " + common::density_scale_options(s, stage) + "\n";
    }
  }
  return out;
}

namespace {

// A found vehicle placed in the tile: its model -> tile pose, the pose's angles and its
// footprint (counter-clockwise corners) from the model's box or the candidate's.
struct Placement {
  Matrix m{};
  std::array<double, 3> e{};
  std::vector<Corner> ring;
  std::string from;
};

Placement place(const Candidate& c, const Verdict& v, const Params& params) {
  Placement p;
  // The tile pose: the verdict's pose_tile when it was given the transform, else composed here.
  p.m = v.pose_tile ? *v.pose_tile : multiply(c.transform, *v.pose);
  p.e = euler_degrees(p.m);
  const Matrix& m = p.m;
  const auto box = v.model.empty() ? params.boxes.end() : params.boxes.find(v.model);
  if (v.model.empty() && v.size) {
    // A class-level answer: its measured rectangle (±L/2, ±W/2) about the pose.
    const double hl = (*v.size)[0] / 2, hw = (*v.size)[1] / 2;
    p.ring = {apply(m, -hl, -hw), apply(m, hl, -hw), apply(m, hl, hw), apply(m, -hl, hw)};
    p.from = "class";
  } else if (box != params.boxes.end()) {
    const ModelBox& b = box->second;
    p.ring = {apply(m, b.x0, b.y0), apply(m, b.x1, b.y0), apply(m, b.x1, b.y1), apply(m, b.x0, b.y1)};
    p.from = "model";
  } else {
    const double hl = c.length / 2, hw = c.width / 2;
    const Matrix& t = c.transform;
    p.ring = {apply(t, -hl, -hw), apply(t, hl, -hw), apply(t, hl, hw), apply(t, -hl, hw)};
    p.from = "candidate";
  }
  // Counter-clockwise seen from above (RFC 7946 exterior rings); the shoelace relative to
  // the first corner, as products of UTM magnitudes would cancel.
  auto& ring = p.ring;
  double area2 = 0;
  for (std::size_t k = 0; k < 4; ++k) {
    const Corner& a = ring[k];
    const Corner& b = ring[(k + 1) % 4];
    area2 += (a[0] - ring[0][0]) * (b[1] - ring[0][1]) - (b[0] - ring[0][0]) * (a[1] - ring[0][1]);
  }
  if (area2 < 0) std::swap(ring[1], ring[3]);
  return p;
}

// The detection's entry in detections.json: model level (the model chain's verdict names a
// model) or class level (classify's answer names a class; "model": null).
documents::DetectionRecord detection_of(const Candidate& c, const Verdict& v, const Placement& p,
                                        const PlattMap& calibration) {
  documents::DetectionRecord d;
  d.candidate = c.id;
  d.model_level = !v.model.empty();
  d.model = v.model;
  d.cls = v.cls;
  d.group = v.group;
  d.confidence = calibrated(calibration, v.confidence);
  d.matrix = p.m;
  d.euler = p.e;
  if (v.heading_ambiguity) d.heading_ambiguity = *v.heading_ambiguity;
  d.size = v.size;
  d.density = v.density;
  d.footprint = p.ring;
  d.footprint_from = p.from;
  d.verdict = v.name;
  return d;
}

// The rejection of a candidate no level answered: classify's reason when it answered, else
// the model chain's none or failure.
documents::RejectionRecord rejection_of(const Candidate& c, const Answers& a, const Calibration& calibration,
                                        double coarse_none_below, std::string& reason) {
  const Verdict& k = a.cls;
  const Verdict& v = a.model;
  // verify's none: its map by the candidate's object density (Params::coarse_none_below; 0: the
  // one none map of before the split).
  const PlattMap& none_map = !(coarse_none_below > 0)                      ? calibration.none
                             : c.density && *c.density < coarse_none_below ? calibration.none_coarse
                                                                           : calibration.none_dense;
  const bool classified = k.present && !k.failed;
  const bool failed = v.present ? v.failed : k.failed;
  reason = classified ? (k.reason.empty() ? "none" : k.reason) : (failed ? "failed" : "none");
  documents::RejectionRecord r;
  r.candidate = c.id;
  r.reason = reason;
  r.classified = classified;
  r.position = std::array<double, 2>{c.transform[3], c.transform[7]};  // the candidate frame's origin
  if (classified) {
    if (!k.detail.empty()) r.detail = k.detail;
    // classify's confidence is a confidence in its none only when it decided one: too_sparse
    // decides nothing (confidence 0), and a class answer left without a detection (no pose, or
    // --size-only's gate) is a confidence in the class (score's reliability of none reads it).
    if (k.cls.empty() && k.reason != "too_sparse")
      r.confidence = calibrated(calibration.none_class, k.confidence);
    // Both levels said none: verify's confidence in its none is the probability that no vehicle
    // stands at the candidate, fitted on tile candidates for exactly this (docs/decisions/
    // verify.md §15); classify's none, fitted on its own gates, stated ~0.999 and was right
    // 88% of the time on development tiles. Calibrated for the rejections of both levels
    // (verify.md §16: verify's fit counts a vehicle classify then finds as "a vehicle is there").
    if (k.cls.empty() && v.present && !v.failed && v.model.empty())
      r.confidence = calibrated(none_map, v.confidence);
    r.density = k.density ? k.density : c.density;
    r.has_density_needed = k.density_class || k.density_model;
    r.density_class = k.density_class;
    r.density_model = k.density_model;
    // What the model chain said, when it ran.
    if (v.present) r.model_chain = v.failed ? "failed" : "none";
    r.verdict = k.name;
  } else {
    r.detail = reason != "failed" ? "the model chain found no model of the modelbase"
               : v.present        ? "a stage of the model chain failed (see the candidate's .log files)"
                                  : "classify failed (see the candidate's class.json.log)";
    if (!(reason == "failed" || !v.present)) r.confidence = calibrated(none_map, v.confidence);
    r.density = c.density;
    r.verdict = v.present ? v.name : k.name;
  }
  return r;
}

}  // namespace

void validate(const Params& params) {
  if (!params.crs.empty() && !formats::is_epsg_code(params.crs)) {
    throw common::UsageError("--crs must be EPSG:<code>, e.g. EPSG:32633");
  }
}

double calibrated(const PlattMap& map, double p) {
  if (map.bias == 0 && map.slope == 1) return p;
  const double q = std::clamp(p, 1e-9, 1 - 1e-9);
  return 1 / (1 + std::exp(-(map.bias + map.slope * std::log(q / (1 - q)))));
}

Calibration parse_calibration(const std::string& text, const std::string& name) {
  Calibration cal;
  cal.name = name;
  std::map<std::string, double*> slot{{"model-bias", &cal.model.bias},
                                      {"model-slope", &cal.model.slope},
                                      {"class-bias", &cal.cls.bias},
                                      {"class-slope", &cal.cls.slope},
                                      {"none-bias", &cal.none.bias},
                                      {"none-slope", &cal.none.slope},
                                      {"none-class-bias", &cal.none_class.bias},
                                      {"none-class-slope", &cal.none_class.slope},
                                      {"none-dense-bias", &cal.none_dense.bias},
                                      {"none-dense-slope", &cal.none_dense.slope},
                                      {"none-coarse-bias", &cal.none_coarse.bias},
                                      {"none-coarse-slope", &cal.none_coarse.slope}};
  formats::IniPolicy policy;  // '#' and ';' comments, no sections, each key once
  policy.keys.assign(std::begin(kCalibrationKeys), std::end(kCalibrationKeys));
  const formats::IniFile file = formats::parse_ini(text, name, policy);
  for (const formats::IniEntry& e : file.entries) {
    const std::string& key = e.key;
    const std::string& value = e.value;
    if (!std::regex_match(value, std::regex("[-+]?([0-9]+\\.?[0-9]*|\\.[0-9]+)([eE][-+]?[0-9]+)?")))
      file.fail(e.line, key + " = " + value + " is not a decimal number");
    const double x = std::stod(value);
    if (!std::isfinite(x) || std::fabs(x) > 1e3)
      file.fail(e.line, key + " = " + value + " is out of range (|value| <= 1000)");
    if (key.size() > 6 && key.compare(key.size() - 6, 6, "-slope") == 0 && !(x > 0))
      file.fail(e.line,
                key + " = " + value + " must be > 0 (a calibration never reorders one level's answers)");
    *slot.at(key) = x;
  }
  for (const char* k : kCalibrationKeys) {
    if (file.find("", k) == nullptr)
      throw common::DataError(name, std::string("has no ") + k + " (every key is needed)");
  }
  return cal;
}

namespace {
std::array<double, 3> box_size(const ModelBox& b) {
  const double lx = b.x1 - b.x0, ly = b.y1 - b.y0;
  return {std::max(lx, ly), std::min(lx, ly), b.z1};
}
}  // namespace

double size_difference(const std::array<double, 3>& size, const ModelBox& box) {
  const auto m = box_size(box);
  double worst = 0;
  for (int i = 0; i < 3; ++i) {
    if (!(m[i] > 0)) return std::numeric_limits<double>::infinity();
    worst = std::max(worst, std::fabs(size[i] - m[i]) / m[i]);
  }
  return worst;
}

std::string nearest_by_size(const std::array<double, 3>& size, const std::map<std::string, ModelBox>& boxes) {
  std::string best;
  double d_best = std::numeric_limits<double>::infinity();
  for (const auto& [name, b] : boxes) {
    const auto m = box_size(b);
    double d = 0;
    for (int i = 0; i < 3; ++i) d += (m[i] - size[i]) * (m[i] - size[i]);
    if (d < d_best) {
      d_best = d;
      best = name;
    }
  }
  return best;
}

Matrix size_only_pose(const Matrix& rect, const ModelBox& b) {
  const double cx = (b.x0 + b.x1) / 2, cy = (b.y0 + b.y1) / 2;
  // model -> rectangle frame: x' = R (x - c), R = identity or a quarter turn (model y along x').
  const bool turn = b.y1 - b.y0 > b.x1 - b.x0;
  const double c = turn ? 0 : 1, s = turn ? -1 : 0;  // Rz(-90°) maps the model's y onto x'
  const Matrix m{c, -s, 0, -(c * cx - s * cy), s, c, 0, -(s * cx + c * cy), 0, 0, 1, 0, 0, 0, 0, 1};
  return multiply(rect, m);
}

bool model_contradicted(const Verdict& v, const Verdict& k, bool by_group) {
  if (v.model.empty() || v.cls.empty() || k.cls.empty()) return false;
  if (k.cls == v.cls || k.group == v.cls) return false;
  return !by_group || common::class_group(v.cls) != (k.group.empty() ? common::class_group(k.cls) : k.group);
}

bool refused_by_shape(const Verdict& v, const Verdict& k) {
  if (v.model.empty() || !k.cls.empty()) return false;
  return k.refused_on == "shape" || k.refused_on == "surface";
}

namespace {

// A rejection whose candidate's model answer `v` was set aside for classify's answer (collect's
// `option`): marked so, and its detail says which model at what confidence.
void set_aside_note(documents::RejectionRecord& r, const Verdict& v, const char* option) {
  r.model_chain = "set_aside";
  char conf[32];
  std::snprintf(conf, sizeof conf, "%.2f", v.confidence);
  r.detail = (r.detail ? *r.detail + "; " : std::string()) + "the model chain's " + v.model +
             " (confidence " + conf + ") set aside for it (collect " + option + ")";
}

}  // namespace

Outputs collect(const Index& index, const std::vector<Answers>& answers, const Params& params,
                const formats::Provenance& provenance) {
  if (answers.size() != index.candidates.size())
    throw common::Error("collect: one answer per candidate expected");
  documents::DetectionsRecord doc;
  Outputs out;
  std::vector<std::string> reasons(answers.size());
  for (std::size_t i = 0; i < answers.size(); ++i) {
    const Candidate& c = index.candidates[i];
    const Verdict& v = answers[i].model;
    const Verdict& k = answers[i].cls;
    for (const Verdict* x : {&v, &k}) {
      if (x->present && !x->failed && !names_candidate(x->candidate, c.id)) {
        throw common::DataError(x->name, "was written for \"" + x->candidate + "\", not for candidate " + c.id);
      }
    }
    if (!v.present && !k.present) {
      throw common::DataError(v.name, "does not exist, nor does " + k.name + ": candidate " + c.id +
                                          " has no answer (run its model chain or classify)");
    }
    if (v.present) {
      ++out.chain_ran;
      out.chain_failed += v.failed ? 1 : 0;
    }
    const Verdict* found = nullptr;
    Verdict by_size;
    const bool classified = k.present && !k.failed && !k.cls.empty() && (k.pose || k.pose_tile);
    // verify's doubtful model answer set aside for classify's refusal on the shape (--refused-below).
    const bool set_aside = !params.size_only && v.present && !v.failed && k.present && !k.failed &&
                           v.confidence < params.refused_below && refused_by_shape(v, k);
    // classify's class answer stating less than --class-accept: never a detection.
    const double class_stated = classified ? calibrated(params.calibration.cls, k.confidence) : 0;
    const bool below_accept = !params.size_only && classified && class_stated < params.class_accept;
    if (params.size_only) {
      if (k.present && !k.failed && k.measured_size && k.measured_centre && k.measured_heading &&
          !params.boxes.empty()) {
        std::array<double, 3> size = *k.measured_size;
        size[0] += k.measured_edge_correction;  // the object's extent, as the model box's
        size[1] += k.measured_edge_correction;
        const std::string model = nearest_by_size(size, params.boxes);
        const double diff = size_difference(size, params.boxes.at(model));
        if (diff <= params.size_gate) {
          by_size = k;
          by_size.model = model;
          by_size.cls.clear();  // none of classify's decisions: the answer is the model alone
          by_size.group.clear();
          by_size.confidence = 1 - diff / params.size_gate;
          // The measured rectangle in the candidate frame (ground z = 0), then in the tile's.
          const double h = *k.measured_heading * common::kDegree, ch = std::cos(h), sh = std::sin(h);
          const Matrix rect_cand{
              ch, -sh, 0, (*k.measured_centre)[0], sh, ch, 0, (*k.measured_centre)[1], 0, 0, 1, 0, 0,
              0,  0,   1};
          by_size.pose_tile = size_only_pose(multiply(c.transform, rect_cand), params.boxes.at(model));
          found = &by_size;
          ++out.model_level;
        }
      }
    } else if (v.present && !v.failed && !v.model.empty() && !set_aside &&
               !(classified && v.confidence < params.contradicted_below &&
                 model_contradicted(v, k, params.contradicted_by_group))) {
      found = &v;
      ++out.model_level;
    } else if (classified && !below_accept) {
      found = &k;
      ++out.class_level;
    }
    if (found) {
      ++out.found;
      // The stated confidence calibrated for the level that answered (the size-only ablation's
      // answers are none of canopy's levels: as they are).
      const PlattMap identity;
      const PlattMap& map = params.size_only ? identity
                            : found == &v    ? params.calibration.model
                                             : params.calibration.cls;
      documents::DetectionRecord d = detection_of(c, *found, place(c, *found, params), map);
      // --model-classes names the class of a model answer without one, and a model answer's
      // class (its own or the file's) gets its group, after every decision above: the decisions
      // read the answers as they are, this changes only what is written.
      if (d.model_level && d.cls.empty() && d.group.empty()) {
        const auto cls = params.model_classes.find(d.model);
        if (cls != params.model_classes.end()) d.cls = cls->second;
      }
      if (d.model_level && !d.cls.empty() && d.group.empty()) d.group = common::class_group(d.cls);
      doc.detections.push_back(std::move(d));
      continue;
    }
    doc.rejected.push_back(rejection_of(c, answers[i], params.size_only ? Calibration{} : params.calibration,
                                        params.coarse_none_below, reasons[i]));
    if (set_aside) set_aside_note(doc.rejected.back(), v, "--refused-below");
    if (below_accept) {
      documents::RejectionRecord& r = doc.rejected.back();
      reasons[i] = kLowConfidence;
      r.reason = reasons[i];
      char conf[64];
      std::snprintf(conf, sizeof conf, "%.3f, below collect --class-accept %g", class_stated,
                    params.class_accept);
      r.detail = "classify's class answer " + k.cls +
                 (k.group.empty() || k.group == k.cls ? "" : " (" + k.group + ")") + " states confidence " +
                 conf + ": not a detection";
      // A model answer it contradicted (--contradicted-below) was set aside for it.
      if (v.present && !v.failed && !v.model.empty()) set_aside_note(r, v, "--contradicted-below");
    }
    ++out.by_reason[reasons[i]];
    // v1's counts: a failed model chain with no class answer, else a "none" (someone looked).
    if (reasons[i] == "failed") {
      ++out.failed;
    } else {
      ++out.none;
    }
  }
  out.warning = warning_of(index, answers, out, reasons, params.size_only);
  out.summary = summary_line(index, out);
  doc.provenance = provenance;
  doc.index = index.name;
  doc.tile = index.tile;
  // --crs wins; else the CRS the tile's file records (detect put it in the index); else none.
  if (!params.crs.empty()) {
    doc.crs = params.crs;
    doc.crs_from = "--crs";
  } else if (!index.crs.empty()) {
    doc.crs = index.crs;
    doc.crs_from = "tile: " + index.crs_from;
  }
  doc.candidates = index.candidates.size();
  doc.found = out.found;
  doc.none = out.none;
  doc.failed = out.failed;
  doc.model_chain_ran = out.chain_ran;
  doc.model_chain_failed = out.chain_failed;
  doc.model_level = out.model_level;
  doc.class_level = out.class_level;
  doc.by_reason = out.by_reason;
  doc.density = index.density;
  doc.warning = out.warning;
  out.detections = documents::serialize_detections(doc);
  out.geojson = documents::serialize_detections_geojson(doc);
  return out;
}

Outputs run(const Params& params, const Inputs& inputs) {
  return collect(inputs.index, inputs.answers, params, inputs.provenance);
}

}  // namespace canopy::collect
