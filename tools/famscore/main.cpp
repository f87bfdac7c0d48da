// famscore: class-level scores of the families protocol from verify's verdicts
// (mk/families.mk, docs/decisions/families.md).
#include <string>

#include "canopy/common/atomic_file.h"
#include "canopy/common/cli.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/documents/verdict.h"
#include "famscore/famscore.h"

namespace cm = canopy::common;
using namespace canopy::famscore;

int main(int argc, char** argv) {
  cm::Tool tool("famscore",
                "Confusion matrix, class accuracy and nearest-instance accuracy of the "
                "vehicle-families protocol from verify's verdicts.");
  tool.without_threads();
  std::string runs_path = "-", modelbase, confusion, accuracy, methods_out, methods_confusion;
  tool.add_input(&runs_path, "runs manifest: <verdict.json> <class> <instance> <cover> <noise> per line");
  tool.add("--modelbase", &modelbase, "the modelbase the verdicts used (<model>.class files)")->required();
  tool.add_output("--confusion", &confusion, "confusion matrix CSV (true class x answered class)")->required();
  tool.add_output("--accuracy", &accuracy, "accuracy CSV per cover and noise level")->required();
  tool.add_output("--methods", &methods_out,
                  "class and nearest-instance accuracy and time of gmatch, verify, VFH and FPFH per class, "
                  "cover and noise level (reads match.json, baseline-vfh.json, baseline-fpfh.json and the "
                  ".time files beside each verdict)");
  tool.add_output("--methods-confusion", &methods_confusion,
                  "one confusion matrix per method (with --methods)");
  return tool.run(argc, argv, [&] {
    if (methods_out.empty() != methods_confusion.empty())
      throw cm::UsageError("--methods and --methods-confusion go together");
    const bool with_methods = !methods_out.empty();
    cm::OutputSet outputs;
    outputs.add(confusion, "--confusion");
    outputs.add(accuracy, "--accuracy");
    if (with_methods) {
      outputs.add(methods_out, "--methods");
      outputs.add(methods_confusion, "--methods-confusion");
    }
    Params p;
    p.with_methods = with_methods;
    const Outputs out = run(p, {cm::read_file(runs_path), cm::display_name(runs_path), modelbase});
    outputs.set(confusion, out.confusion);
    outputs.set(accuracy, out.accuracy);
    if (with_methods) {
      outputs.set(methods_out, out.methods);
      outputs.set(methods_confusion, out.methods_confusion);
    }
    outputs.commit();
    const std::string all = out.accuracy.substr(out.accuracy.rfind("all,all"));
    cm::log::info(std::to_string(out.trials) + " trials, " + std::to_string(out.entries) +
                  " modelbase entries: " + all.substr(0, all.size() - 1));
  });
}
