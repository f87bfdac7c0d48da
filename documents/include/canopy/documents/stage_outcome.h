// What a stage left behind in its output file (tools/stagerun): no file (the stage did not
// run), an empty file (the stage failed: stagerun --record-failure leaves an empty output so
// that make goes on), else the document the stage wrote. The one place that reads this rule;
// every reader of a stage's output that may have failed asks here first.
#pragma once

#include <string>

#include "canopy/documents/verdict.h"

namespace canopy::documents {

enum class StageOutcome { missing, failed, written };

struct StageOutput {
  StageOutcome outcome = StageOutcome::missing;
  std::string text;  // the file's contents when written
};

// The outcome of a stage's output from its contents: empty = failed, else written.
StageOutcome stage_outcome_of(const std::string& text);
// The file at `path`: missing when there is no such file (nor a link to one), else its
// contents (common::read_file: DataError naming the file when it cannot be read) and outcome.
StageOutput read_stage_output(const std::string& path);

// A verdict a stage wrote (verify, baseline --verdict, classify): its outcome and, when
// written, the verdict read (read_verdict's refusals, naming the file).
struct StageVerdict {
  StageOutcome outcome = StageOutcome::missing;
  Verdict verdict;  // when outcome == written
};
StageVerdict read_stage_verdict(const std::string& path);
// The same from the contents `text` of file `name` (a file that exists).
StageVerdict parse_stage_verdict(const std::string& text, const std::string& name);

}  // namespace canopy::documents
