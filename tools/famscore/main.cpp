// famscore: class-level scores of the families protocol from verify's verdicts
// (mk/families.mk, docs/decisions/families.md).
#include <algorithm>
#include <filesystem>
#include <sstream>
#include <string>

#include "canopy/common/atomic_file.h"
#include "canopy/common/cli.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/formats/verdict.h"
#include "famscore/famscore.h"

namespace cm = canopy::common;
namespace fs = std::filesystem;
using namespace canopy::famscore;

int main(int argc, char** argv) {
  cm::Tool tool("famscore",
                "Confusion matrix, class accuracy and nearest-instance accuracy of the "
                "vehicle-families protocol from verify's verdicts.");
  tool.without_threads();
  std::string runs_path = "-", modelbase, confusion, accuracy;
  tool.add_input(&runs_path, "runs manifest: <verdict.json> <class> <instance> <cover> <noise> per line");
  tool.add("--modelbase", &modelbase, "the modelbase the verdicts used (<model>.class files)")->required();
  tool.add_output("--confusion", &confusion, "confusion matrix CSV (true class x answered class)")->required();
  tool.add_output("--accuracy", &accuracy, "accuracy CSV per cover and noise level")->required();
  return tool.run(argc, argv, [&] {
    cm::OutputSet outputs;
    outputs.add(confusion, "--confusion");
    outputs.add(accuracy, "--accuracy");
    const auto runs = parse_runs(cm::read_file(runs_path), cm::display_name(runs_path));
    std::error_code ec;
    if (!fs::is_directory(modelbase, ec))
      throw cm::DataError(modelbase, "modelbase directory does not exist");
    std::vector<Entry> entries;
    std::vector<fs::path> files;
    for (const auto& f : fs::directory_iterator(modelbase)) {
      if (f.path().extension() == ".class") files.push_back(f.path());
    }
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
      std::istringstream in(cm::read_file(f.string()));
      std::string word;
      if (!(in >> word)) throw cm::DataError(f.string(), "empty class file");
      entries.push_back({f.stem().string(), word});
    }
    if (entries.empty())
      throw cm::DataError(modelbase, "no <model>.class file: the modelbase carries no classes");
    std::vector<Trial> trials;
    for (const auto& r : runs) {
      Trial t;
      t.run = r;
      t.expected_nearest = nearest_by_size(r.vehicle_class, r.instance, entries);
      if (cm::read_file(r.verdict).empty()) {  // a stage failed on this trial
        t.answered_class = "none";
        t.failed = true;
        trials.push_back(t);
        continue;
      }
      const canopy::formats::Verdict v = canopy::formats::read_verdict(r.verdict);
      if (!v.has_classes)
        throw cm::DataError(r.verdict, "verdict names no class (modelbase without classes?)");
      t.answered_class = v.vehicle_class.empty() ? "none" : v.vehicle_class;
      t.nearest = v.nearest_instance;
      t.accepted = !v.model.empty();
      trials.push_back(t);
    }
    outputs.set(confusion, confusion_csv(trials, entries));
    const std::string acc = accuracy_csv(trials);
    outputs.set(accuracy, acc);
    outputs.commit();
    const std::string all = acc.substr(acc.rfind("all,all"));
    cm::log::info(std::to_string(trials.size()) + " trials, " + std::to_string(entries.size()) +
                  " modelbase entries: " + all.substr(0, all.size() - 1));
  });
}
