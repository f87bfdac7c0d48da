#include "report/openset_section.h"

#include <map>
#include <sstream>

#include "report/score_cells.h"
#include "report/report.h"

namespace canopy::report {

std::string openset_markdown(const documents::SceneScore& score, const std::string& score_path) {
  std::ostringstream md;
  md << "\n## Open set: unseen vehicles\n\n"
     << "The scene experiment's tiles (its recipe and cover levels, noise 0) with their vehicles drawn "
        "from the vehicle library's **test** instances only (share/vehicles/split.csv: third-party meshes "
        "never in the modelbase), recognised against a modelbase built by `make user-modelbase` from the "
        "library's **modelbase** instances (share/vehicles/modelbase/). No answer can name the right "
        "instance, so what is judged is the class: a model answer names its entry's class, a class "
        "answer its class or group (score --model-classes). Either level counts as found. Rates: k/n "
        "and score's 95% interval (mk/openset.mk; docs/decisions/open-set.md; "
     << score_path << ").\n\n";
  md << "| cover | tiles | vehicles | found (model + class) | recall | precision | class right (of found) | "
        "false alarms/ha |\n|---|---|---|---|---|---|---|---|\n";
  for (const documents::ScoreRow* r : cover_rows(score)) {
    const documents::ScoreValue* c = documents::score_cell(*r, "cover");
    md << "| " << (c ? c->text : "") << " | " << score_count(*r, "tiles") << " | " << score_count(*r, "true")
       << " | " << score_count(*r, "found_any_level") << " (" << score_count(*r, "tp") << " + "
       << score_count(*r, "class_tp") << ") | " << score_ci(*r, "recall_any_level", "%.1f%%", "%.1f", 100)
       << " | " << score_ci(*r, "precision_any_level", "%.1f%%", "%.1f", 100) << " | "
       << score_count(*r, "class_right_any_level") << "/" << score_count(*r, "found_any_level") << " = "
       << score_ci(*r, "class_accuracy_any_level", "%.1f%%", "%.1f", 100) << " | "
       << score_ci(*r, "false_alarms_any_level_per_ha", "%.1f", "%.1f", 1) << " |\n";
  }
  // Per test instance: found, by level, and the classes (or models) answered.
  struct Tally {
    int all = 0, found = 0, model = 0, cls = 0;
    std::map<std::string, int> answers;
  };
  std::map<std::string, Tally> per;
  for (const documents::ScoreMatch& m : score.matches) {
    if (!m.true_model || m.outcome == "false_alarm") continue;
    Tally& t = per[*m.true_model];
    ++t.all;
    if (m.outcome != "right" && m.outcome != "wrong") continue;
    ++t.found;
    const bool model = m.level.value_or("model") == "model";
    ++(model ? t.model : t.cls);
    ++t.answers[(model ? "model " + m.model.value_or("?") + " (" + m.cls.value_or("no class") + ")"
                       : "class " + m.cls.value_or("?"))];
  }
  md << "\n| test instance | found / true | at model / class level | answers |\n|---|---|---|---|\n";
  for (const auto& [name, t] : per) {
    std::string answers;
    for (const auto& [a, n] : t.answers)
      answers += (answers.empty() ? "" : ", ") + a + " × " + std::to_string(n);
    md << "| " << name << " | " << t.found << "/" << t.all << " | " << t.model << " / " << t.cls << " | "
       << (answers.empty() ? "–" : answers) << " |\n";
  }
  return md.str();
}

}  // namespace canopy::report
