#include "canopy/documents/candidate_truth.h"

#include <set>
#include <string>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/formats/json_document.h"
#include "members.h"

namespace canopy::documents {
namespace {

using namespace members;  // NOLINT(google-build-using-namespace): the document's member helpers

double share(const Json& j, const char* key, const std::string& w) {
  const double v = finite_number(at(j, key, w), path(w, key));
  if (v < 0 || v > 1) throw Malformed(path(w, key) + " must be a share in [0, 1]");
  return v;
}

}  // namespace

std::string write_candidate_truth(const CandidateTruth& t, const formats::Provenance& prov) {
  auto finite = [](double v) { return finite_or_throw(v, "candtruth"); };
  Json j{{"format", kCandidateTruthFormat},
         {"version", kCandidateTruthVersion},
         {"provenance", formats::provenance_json(prov)},
         {"tile", t.tile},
         {"index", t.index}};
  Json cands = Json::array();
  for (const CandidateTruthRow& c : t.candidates) {
    cands.push_back(Json{{"id", c.id},
                         {"crop_points", c.crop_points},
                         {"instance", c.instance},
                         {"points", c.points},
                         {"coverage", finite(c.coverage)},
                         {"purity", finite(c.purity)}});
  }
  j["candidates"] = std::move(cands);
  Json inst = Json::array();
  for (const InstanceTruthRow& it : t.instances) {
    inst.push_back(Json{{"instance", it.instance}, {"points", it.points}, {"candidates", it.candidates}});
  }
  j["instances"] = std::move(inst);
  return j.dump(1) + "\n";
}

CandidateTruth read_candidate_truth(const std::string& body, const std::string& name) {
  const Json j =
      formats::open_json_document(body, name, kCandidateTruthFormat, nullptr, kCandidateTruthVersion);
  CandidateTruth t;
  try {
    t.tile = text(at(j, "tile", ""), "tile");
    t.index = text(at(j, "index", ""), "index");
    const Json& cs = array(at(j, "candidates", ""), "candidates");
    std::set<std::string> ids;
    for (std::size_t k = 0; k < cs.size(); ++k) {
      const std::string w = "candidates[" + std::to_string(k) + "]";
      object(cs[k], w);
      CandidateTruthRow c;
      c.id = text(at(cs[k], "id", w), path(w, "id"));
      if (!ids.insert(c.id).second) throw Malformed(path(w, "id") + " \"" + c.id + "\" repeats");
      c.crop_points = count(at(cs[k], "crop_points", w), path(w, "crop_points"));
      c.instance = count(at(cs[k], "instance", w), path(w, "instance"));
      c.points = count(at(cs[k], "points", w), path(w, "points"));
      c.coverage = share(cs[k], "coverage", w);
      c.purity = share(cs[k], "purity", w);
      t.candidates.push_back(std::move(c));
    }
    const Json& is = array(at(j, "instances", ""), "instances");
    for (std::size_t k = 0; k < is.size(); ++k) {
      const std::string w = "instances[" + std::to_string(k) + "]";
      object(is[k], w);
      InstanceTruthRow it;
      it.instance = count(at(is[k], "instance", w), path(w, "instance"));
      it.points = count(at(is[k], "points", w), path(w, "points"));
      const Json& c = array(at(is[k], "candidates", w), path(w, "candidates"));
      for (std::size_t m = 0; m < c.size(); ++m) {
        const std::string id = text(c[m], path(w, "candidates") + "[" + std::to_string(m) + "]");
        if (!ids.count(id)) throw Malformed(path(w, "candidates") + ": \"" + id + "\" is not a candidate");
        it.candidates.push_back(id);
      }
      t.instances.push_back(std::move(it));
    }
  } catch (const Malformed& e) {
    throw common::DataError(name, std::string("bad canopy.candidate_truth document: ") + e.what());
  }
  return t;
}

CandidateTruth read_candidate_truth_file(const std::string& path) {
  return read_candidate_truth(common::read_file(path), path);
}

}  // namespace canopy::documents
