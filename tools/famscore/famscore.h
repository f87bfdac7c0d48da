// famscore: class-level scores of the families protocol (issue 17, mk/families.mk) from
// verify's verdicts: the confusion matrix of true class vs answered class, class accuracy and
// nearest-instance accuracy per cover and noise level (docs/decisions/families.md).
//
// The runs manifest has one trial per line: <verdict.json> <class> <instance> <cover> <noise>
// (the test vehicle is family:<class>:<instance>; '#' starts a comment). The answered class is
// the verdict's "class" (the best-scoring hypothesis's class, accepted or not); "none" when the
// verdict has no class or is empty (a stage failed on the trial: stage.sh --record-failure). The right
// nearest instance is the modelbase entry of the true class whose generated length, width and height are
// nearest (Euclidean) to the test vehicle's.
#pragma once

#include <string>
#include <vector>

namespace canopy::famscore {

struct Run {
  std::string verdict, vehicle_class, cover, noise;
  int instance = 0;
  int line = 0;
};

// Parses the manifest; DataError naming `name` and the line on a malformed line.
std::vector<Run> parse_runs(const std::string& text, const std::string& name);

// A modelbase entry with a class (<model>.class).
struct Entry {
  std::string model, vehicle_class;
};

// The entry of class `vehicle_class` nearest in size to family:<class>:<instance> among the
// entries named <class>-<n> (generated instances); "" when there is none.
std::string nearest_by_size(const std::string& vehicle_class, int instance, const std::vector<Entry>& entries);

struct Trial {
  Run run;
  std::string answered_class;  // "none" when the verdict names no class
  std::string nearest, expected_nearest;
  bool accepted = false;  // the verdict's model passed verify's threshold
  bool failed = false;    // a stage failed (empty verdict, stage.sh --record-failure)
};

// Class order: the families' order, then any other class alphabetically.
std::vector<std::string> class_order(const std::vector<std::string>& classes);

// true_class,<answered classes...>,none — counts of trials.
std::string confusion_csv(const std::vector<Trial>& trials, const std::vector<Entry>& entries);
// cover,noise,trials,class_right,class_accuracy,accepted,accepted_right,nearest_right,
// nearest_accuracy,failed — one row per (cover, noise) in first-seen order, then all,all.
// accepted = verify accepted the nearest instance as the model; failed trials count as wrong.
std::string accuracy_csv(const std::vector<Trial>& trials);

}  // namespace canopy::famscore
