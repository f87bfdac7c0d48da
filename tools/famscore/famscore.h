// famscore: class-level scores of the families protocol (issue 17, mk/families.mk) from
// verify's verdicts: the confusion matrix of true class vs answered class, class accuracy and
// nearest-instance accuracy per cover and noise level (docs/decisions/families.md).
//
// The runs manifest has one trial per line: <verdict.json> <class> <instance> <cover> <noise>
// (the test vehicle is family:<class>:<instance>; '#' starts a comment). The answered class is
// the verdict's "class" (the best-scoring hypothesis's class, accepted or not); "none" when the
// verdict has no class or is empty (a stage failed on the trial: stagerun --record-failure). The right
// nearest instance is the modelbase entry of the true class whose generated length, width and height are
// nearest (Euclidean) to the test vehicle's.
//
// Methods side by side (docs/decisions/families.md §10): beside verify's answer, the class of
// gmatch's rank-1 model (match.json) and of the PCL baseline's rank-1 model per method
// (baseline-vfh.json, baseline-fpfh.json), all in the verdict's directory, with each method's
// time from the stages' .time files (tools/stagerun: wall seconds, peak KiB).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "canopy/documents/family_runs.h"

namespace canopy::famscore {

// One trial of the runs manifest (documents/family_runs.h).
using Run = documents::FamilyRun;

// A modelbase entry with a class (<model>.class).
struct Entry {
  std::string model, vehicle_class;
};

// The entry of class `vehicle_class` nearest in size to family:<class>:<instance> among the
// entries named <class>-<n> (generated instances); "" when there is none.
std::string nearest_by_size(const std::string& vehicle_class, int instance, const std::vector<Entry>& entries);

// The methods compared, in table order: canopy's gmatch rank-1 and verify's class answer, the
// PCL baseline's VFH and FPFH rank-1.
const std::vector<std::string>& methods();

// The files of a trial that each method's time sums (its stages after the shared fitvox):
// gmatch = cocone + ncut + gmatch, verify = those + verify, vfh / fpfh = the baseline's run.
std::vector<std::string> method_stages(const std::string& method);

// One method's answer on a trial.
struct Answer {
  std::string model;  // rank-1 model, or verify's nearest instance; "" = none
  std::string answered_class = "none";
  bool failed = false;  // its output is empty (a stage failed: --record-failure)
  bool timed = false;   // every stage of method_stages has a readable .time
  double seconds = 0;   // their wall seconds, summed
};

struct Trial {
  Run run;
  std::string answered_class;  // "none" when the verdict names no class
  std::string nearest, expected_nearest;
  bool accepted = false;        // the verdict's model passed verify's threshold
  bool failed = false;          // a stage failed (empty verdict, stagerun --record-failure)
  std::vector<Answer> answers;  // per methods(), when read with them
};

// The <model>.class files of a modelbase directory, sorted by model; DataError naming the
// directory or file when it does not exist, a class file is not one word of at most 64
// characters (documents::read_model_class), or none is found.
std::vector<Entry> read_entries(const std::string& modelbase);

// Reads one trial from the verdict (and, with `with_methods`, the other methods' files beside
// it: match.json, baseline-vfh.json, baseline-fpfh.json and every stage's .time). DataError
// naming the file when one is missing or malformed; an empty file is a failed stage.
Trial read_trial(const Run& run, const std::vector<Entry>& entries, bool with_methods);

// Class order: the families' order, then any other class alphabetically.
std::vector<std::string> class_order(const std::vector<std::string>& classes);

// true_class,<answered classes...>,none — counts of trials.
std::string confusion_csv(const std::vector<Trial>& trials, const std::vector<Entry>& entries);
// cover,noise,trials,class_right,class_accuracy,accepted,accepted_right,nearest_right,
// nearest_accuracy,failed — one row per (cover, noise) in first-seen order, then all,all.
// accepted = verify accepted the nearest instance as the model; failed trials count as wrong.
std::string accuracy_csv(const std::vector<Trial>& trials);

// method,class,cover,noise,trials,class_right,class_accuracy,nearest_right,nearest_accuracy,
// failed,timed,seconds_mean — per method: all,all,all; each class (all,all); each cover (all
// classes and noises); each noise level (all classes and covers). Failed trials count as wrong;
// seconds_mean is over the timed trials (empty when none).
std::string methods_csv(const std::vector<Trial>& trials);
// method,true_class,<answered classes...>,none — one confusion matrix per method, same columns.
std::string methods_confusion_csv(const std::vector<Trial>& trials, const std::vector<Entry>& entries);

// ---- the stage

struct Params {
  bool with_methods = false;  // also the methods tables (gmatch, verify, VFH, FPFH side by side)
};

// Nothing in Params can be out of range (kept for the one stage shape; the CLI refuses
// --methods without --methods-confusion itself).
inline void validate(const Params&) {}

struct Inputs {
  std::string runs_text, runs_name;  // the manifest and the name its errors give
  std::string modelbase;             // directory of <model>.class files
};

struct Outputs {
  std::string confusion, accuracy;         // confusion_csv, accuracy_csv
  std::string methods, methods_confusion;  // with_methods only
  std::size_t trials = 0, entries = 0;     // what was read
};

// Reads the manifest's trials and the modelbase's classes, and renders the tables.
Outputs run(const Params& params, const Inputs& inputs);

}  // namespace canopy::famscore
