#include "canopy/documents/family_runs.h"

#include "canopy/common/error.h"
#include "canopy/formats/text_lines.h"

namespace canopy::documents {

std::vector<FamilyRun> parse_family_runs(const std::string& text, const std::string& name) {
  std::vector<FamilyRun> runs;
  for (const formats::TextLine& l : formats::text_lines(text)) {
    const std::vector<std::string>& w = l.words;
    const std::string where = "line " + std::to_string(l.number) + ": ";
    if (w.size() != 5)
      throw common::DataError(name, where + "expected <verdict> <class> <instance> <cover> <noise>");
    if (w[2].size() > 9 || w[2].find_first_not_of("0123456789") != std::string::npos) {
      throw common::DataError(name, where + "instance '" + w[2] + "' is not a number 0..999999999");
    }
    FamilyRun r;
    r.verdict = w[0];
    r.vehicle_class = w[1];
    r.instance = std::stoi(w[2]);
    r.cover = w[3];
    r.noise = w[4];
    r.line = l.number;
    runs.push_back(r);
  }
  if (runs.empty()) throw common::DataError(name, "no trial in the runs manifest");
  return runs;
}

}  // namespace canopy::documents
