// The report's "Vehicle families" section (issue 17; docs/decisions/families.md): class accuracy
// per class and overall, the confusion matrix and nearest-instance accuracy of the class-level
// protocol (mk/families.mk), from famscore's results/families/{confusion.csv, accuracy.csv}.
// summarize_families computes the numbers; families_markdown only renders them.
#pragma once

#include <string>
#include <vector>

#include "canopy/documents/family_tables.h"

namespace canopy::report {

// One true class: its row of the confusion matrix (counts per answered class, in
// FamilySummary::answers order).
struct FamilyClass {
  std::string name;
  std::vector<int> answered;
  int trials = 0, right = 0;  // right = the answered class is the true class
};

// One method's confusion matrix (methods-confusion.csv), columns FamilySummary::method_answers.
struct FamilyMethodConfusion {
  std::string method;
  std::vector<FamilyClass> classes;
};

struct FamilySummary {
  std::vector<std::string> answers;  // confusion.csv's answered classes (columns), "none" included
  std::vector<FamilyClass> classes;  // confusion.csv's rows, in order
  std::vector<documents::FamilyAccuracyRow> levels;  // accuracy.csv's rows but the total, in order
  documents::FamilyAccuracyRow all;                  // accuracy.csv's "all,all" row
  int trials = 0, right = 0;                         // over the confusion matrix
  // canopy beside the PCL baseline (famscore --methods), empty when the tables are absent.
  std::vector<std::string> methods;                     // in methods.csv order (gmatch, verify, vfh, fpfh)
  std::vector<documents::FamilyMethodRow> method_rows;  // in methods.csv order
  std::vector<std::string> method_answers;              // methods-confusion.csv's answered classes
  std::vector<FamilyMethodConfusion> method_confusion;
};

// Parses famscore's two tables (names for the errors). When famscore's methods.csv and
// methods-confusion.csv lie beside `accuracy_name` (a path; the report passes DIR/accuracy.csv)
// they are read too (add_family_methods); one without the other is a DataError. DataError naming the file and line on
// a malformed table, and when the two disagree (trials or right class answers in total). A true
// class without a column of its own (no entry and never answered) has no right answers.
FamilySummary summarize_families(const std::string& confusion, const std::string& confusion_name,
                                 const std::string& accuracy, const std::string& accuracy_name);

// Adds famscore's methods.csv and methods-confusion.csv (names for the errors) to `s`. DataError
// naming the file and line on a malformed table, a method without its all,all,all row, and when
// the tables disagree with each other or with `s` (verify's totals must be the confusion
// matrix's: the same trials and right class answers).
void add_family_methods(FamilySummary& s, const std::string& methods, const std::string& methods_name,
                        const std::string& confusion, const std::string& confusion_name);

std::string families_markdown(const FamilySummary& s);

}  // namespace canopy::report
