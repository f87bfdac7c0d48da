// The report's "Open set: unseen vehicles" section (issue 29; mk/openset.mk,
// docs/decisions/open-set.md): the scene experiment's tiles with vehicles drawn from the vehicle
// library's test instances only, recognised against a modelbase of its other instances; the
// single-vehicle crops of the same test instances; and instance accuracy by the library's
// geometric distance (share/vehicles/distances.csv, scripts/vehicles/distance.py).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "canopy/documents/scene_score.h"

namespace canopy::report {

// One row of distances.csv: a modelbase instance of the test instance's class and its distance.
struct OpensetNeighbour {
  std::string modelbase, cls;  // the instance's name and class (its entry is <class>__<name>)
  double distance_m = 0;
  int rank = 0;  // 1 = nearest
};
// Per test instance, its class's modelbase instances by rank.
using OpensetDistances = std::map<std::string, std::vector<OpensetNeighbour>>;

// distances.csv (header test,class,modelbase,distance_m,rank; ranks 1..n per test instance, by
// distance). DataError naming `name` and the line on a malformed file.
OpensetDistances parse_openset_distances(const std::string& text, const std::string& name);

// The modelbase entry nearest to the test instance `test` ("<class>__<name>"), "" when unknown.
std::string openset_nearest_entry(const OpensetDistances& d, const std::string& test);

// Instance accuracy over a score's matches: of the model-level answers (right or wrong) on a
// vehicle whose true model has a row in `d`, how many name its nearest entry.
struct InstanceTally {
  int model_answers = 0, nearest = 0;
};
InstanceTally openset_instance_tally(const documents::SceneScore& score, const OpensetDistances& d);

// The section (Markdown). `score`: the open-set tiles (per cover level the rates with their 95%
// intervals: recall, precision, class right, false alarms per ha; per test instance what the
// answers were). `crops` (may be null): the single-vehicle crops, one cover label per class.
// `distances` (may be empty): each test instance's nearest modelbase instance and the instance
// accuracy of the model-level answers, for the tiles and for the crops.
std::string openset_markdown(const documents::SceneScore& score, const std::string& score_path,
                             const documents::SceneScore* crops = nullptr, const std::string& crops_path = "",
                             const OpensetDistances& distances = {}, const std::string& distances_path = "");

// The open set's classify ablations (mk/openset.mk OPENSET_CLASSIFY_ABLATION[_2|_3|_4]: the same
// candidates and model chain classified with other parameters), each known by its name, which
// picks its heading and paragraph:
//   every-family      OPENSET_CLASSES_ONLY=0 OPENSET_CLASS_ENVELOPE=0: every family, without
//                     --modelbase-classes-only and --class-envelope (the base's parameters alone);
//   no-envelope       the class envelope alone off (class-envelope = 0, --modelbase-classes-only
//                     kept): what the envelope alone changes;
//   family-entries-1  family-entries = 1 (a class one modelbase entry names keeps its whole
//                     family's range): what the eleventh round changes;
//   no-bed            the pickup's bed cue alone off (min-bed = 0): what classify.md §39 changes.
// The names in that order (report's help, the tests).
const std::vector<std::string>& openset_classify_ablation_names();
// The ablation named `name` as a subsection: the tiles' table (`tiles`) and the crops' (`crops`,
// may be null) in the same form as the section's. Throws common::UsageError naming
// --openset-classify-ablation and the names for any other name.
std::string openset_classify_ablation_markdown(const std::string& name, const documents::SceneScore& tiles,
                                               const std::string& tiles_path,
                                               const documents::SceneScore* crops = nullptr,
                                               const std::string& crops_path = "");
// collect's options of an open-set collect ablation (an entry of mk/openset.mk
// OPENSET_COLLECT_ABLATIONS: --name=value options separated by commas or spaces) as collect's
// command line words ("--contradicted-below", "0", ...). Throws common::UsageError naming
// --openset-collect-ablation-options for a word that is not an option.
std::vector<std::string> collect_ablation_options(const std::string& options);
// An ablation of collect's defaults on the same verdicts and class answers, in the same form, its
// heading and paragraph from what its options turn off: none or --contradicted-below=0
// --refused-below=0, verify's model answer first, whatever its confidence; --contradiction-level=class,
// the contradiction by class before the thirteenth round; any other, its options.
std::string openset_collect_ablation_markdown(const documents::SceneScore& tiles, const std::string& tiles_path,
                                              const documents::SceneScore* crops = nullptr,
                                              const std::string& crops_path = "",
                                              const std::string& options = "");
// An ablation of verify's defaults on the open set's tiles (mk/openset.mk OPENSET_VERIFY_ABLATION:
// verify again on every model-level candidate with `options` after its parameters, collected and
// scored the same way), in the same form; --max-tilt=180 is verify without its upright bound.
std::string openset_verify_ablation_markdown(const documents::SceneScore& tiles,
                                             const std::string& tiles_path, const std::string& options);

}  // namespace canopy::report
