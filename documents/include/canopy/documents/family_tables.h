// famscore's family tables (the families protocol, mk/families.mk, docs/decisions/families.md):
// four CSV files, famscore writes them and report's families section reads them. Comma
// separated, no quoting (no cell holds a comma), a header line first; blank lines and a final
// "\r" are skipped when reading.
//   confusion.csv          true_class,<answered classes...>,none — trials per (true, answered)
//   accuracy.csv           cover,noise,trials,class_right,class_accuracy,accepted,accepted_right,
//                          nearest_right,nearest_accuracy,failed — per (cover, noise), then all,all
//   methods.csv            method,class,cover,noise,trials,class_right,class_accuracy,nearest_right,
//                          nearest_accuracy,failed,timed,seconds_mean — per method and slice
//   methods-confusion.csv  method,true_class,<answered classes...>,none — one matrix per method
// The *_accuracy columns are derived (right / trials, "%.4f") and not read back; seconds_mean is
// "%.3f", empty without timed trials. Every refusal is a common::DataError naming the file and
// the line.
#pragma once

#include <string>
#include <vector>

namespace canopy::documents {

// confusion.csv (per_method false) or methods-confusion.csv (true).
struct FamilyConfusion {
  struct Row {
    std::string method;  // methods-confusion.csv only ("" in confusion.csv)
    std::string true_class;
    std::vector<int> answered;  // per `answers`
  };
  std::vector<std::string> answers;  // the answered classes (columns), "none" included
  std::vector<Row> rows;             // as written: per method (if any), the true classes
};

// One row of accuracy.csv.
struct FamilyAccuracyRow {
  std::string cover, noise;
  int trials = 0, class_right = 0, accepted = 0, accepted_right = 0, nearest_right = 0, failed = 0;
};

// One row of methods.csv: a method's counts on a slice of the trials ("all" for the others).
struct FamilyMethodRow {
  std::string method, vehicle_class, cover, noise;
  int trials = 0, class_right = 0, nearest_right = 0, failed = 0, timed = 0;
  double seconds_mean = 0;  // over the timed trials (0 when none)
};

std::string serialize_family_confusion(const FamilyConfusion& table, bool per_method);
std::string serialize_family_accuracy(const std::vector<FamilyAccuracyRow>& rows);  // trials > 0
std::string serialize_family_methods(const std::vector<FamilyMethodRow>& rows);     // trials > 0

// The header (true_class / method,true_class first), then rows as wide as the header of whole
// counts >= 0. Refused: an empty table, another header, a row of another width, a cell that is
// not a count.
FamilyConfusion parse_family_confusion(const std::string& text, const std::string& name, bool per_method);
// Columns by name (any order, others ignored); refused also: a missing column, a count above its
// total (class_right, accepted, nearest_right, failed <= trials; accepted_right <= accepted).
std::vector<FamilyAccuracyRow> parse_family_accuracy(const std::string& text, const std::string& name);
// As accuracy.csv; also refused: an empty method, timed > trials, seconds_mean that is not a time
// >= 0 when timed > 0 or not empty when timed is 0.
std::vector<FamilyMethodRow> parse_family_methods(const std::string& text, const std::string& name);

}  // namespace canopy::documents
