// The families protocol's runs manifest (mk/families.mk writes $(FAM_DIR)/runs.txt at parse time
// when its text changed; famscore reads it): one trial a line,
// "<verdict.json> <class> <instance> <cover> <noise>" (the test vehicle is
// family:<class>:<instance>), blanks between fields, '#' starts a comment, blank lines skipped.
// Every refusal is a common::DataError naming the file and the line.
#pragma once

#include <string>
#include <vector>

namespace canopy::documents {

struct FamilyRun {
  std::string verdict, vehicle_class, cover, noise;
  int instance = 0;  // 0..999999999
  int line = 0;      // the line of the manifest it was read from
};

// The runs in `text` (of file `name`); at least one.
std::vector<FamilyRun> parse_family_runs(const std::string& text, const std::string& name);

}  // namespace canopy::documents
