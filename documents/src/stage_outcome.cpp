#include "canopy/documents/stage_outcome.h"

#include <filesystem>

#include "canopy/common/atomic_file.h"

namespace canopy::documents {

StageOutcome stage_outcome_of(const std::string& text) {
  return text.empty() ? StageOutcome::failed : StageOutcome::written;
}

StageOutput read_stage_output(const std::string& path) {
  StageOutput out;
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return out;
  out.text = common::read_file(path);
  out.outcome = stage_outcome_of(out.text);
  return out;
}

StageVerdict parse_stage_verdict(const std::string& text, const std::string& name) {
  StageVerdict v;
  v.outcome = stage_outcome_of(text);
  if (v.outcome == StageOutcome::written) v.verdict = parse_verdict(text, name);
  return v;
}

StageVerdict read_stage_verdict(const std::string& path) {
  const StageOutput out = read_stage_output(path);
  if (out.outcome == StageOutcome::missing) return {};
  return parse_stage_verdict(out.text, path);
}

}  // namespace canopy::documents
