// The report's "Vehicle families" section (issue 17; docs/decisions/families.md): class accuracy
// per class and overall, the confusion matrix and nearest-instance accuracy of the class-level
// protocol (mk/families.mk), from famscore's results/families/{confusion.csv, accuracy.csv}.
// summarize_families computes the numbers; families_markdown only renders them.
#pragma once

#include <string>
#include <vector>

namespace canopy::report {

// One true class: its row of the confusion matrix (counts per answered class, in
// FamilySummary::answers order).
struct FamilyClass {
  std::string name;
  std::vector<int> answered;
  int trials = 0, right = 0;  // right = the answered class is the true class
};

// One row of accuracy.csv (a cover and noise level, or "all","all").
struct FamilyLevel {
  std::string cover, noise;
  int trials = 0, class_right = 0, accepted = 0, accepted_right = 0, nearest_right = 0, failed = 0;
};

struct FamilySummary {
  std::vector<std::string> answers;  // confusion.csv's answered classes (columns), "none" included
  std::vector<FamilyClass> classes;  // confusion.csv's rows, in order
  std::vector<FamilyLevel> levels;   // accuracy.csv's rows but the total, in order
  FamilyLevel all;                   // accuracy.csv's "all,all" row
  int trials = 0, right = 0;         // over the confusion matrix
};

// Parses famscore's two tables (names for the errors). DataError naming the file and line on
// a malformed table, and when the two disagree (trials or right class answers in total). A true
// class without a column of its own (no entry and never answered) has no right answers.
FamilySummary summarize_families(const std::string& confusion, const std::string& confusion_name,
                                 const std::string& accuracy, const std::string& accuracy_name);

std::string families_markdown(const FamilySummary& s);

}  // namespace canopy::report
