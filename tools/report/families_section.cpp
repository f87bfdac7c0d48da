#include "report/families_section.h"

#include <algorithm>
#include <array>
#include <filesystem>
#include <set>
#include <sstream>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/documents/family_tables.h"
#include "report/report.h"

namespace canopy::report {

std::string method_label(const std::string& m) {
  if (m == "gmatch") return "canopy (gmatch rank-1)";
  if (m == "verify") return "canopy (verify)";
  if (m == "vfh") return "VFH";
  if (m == "fpfh") return "FPFH";
  if (m == "size") return "size only (ablation)";
  if (m == "fpfh-verify") return "FPFH poses, verify (ablation)";
  return m;
}

namespace {

// How many noise levels each test render is run at: accuracy.csv's cover x noise rows over its
// covers (the grid is full: every cover at every noise level). A row that pools the noise
// levels has trials / this many distinct renders.
double noise_copies(const FamilySummary& s) {
  std::set<std::string> covers;
  for (const auto& l : s.levels) covers.insert(l.cover);
  return covers.empty() ? 1.0 : std::max(1.0, static_cast<double>(s.levels.size()) / covers.size());
}

const documents::FamilyMethodRow* method_row(const FamilySummary& s, const std::string& m,
                                             const std::string& cls, const std::string& cover,
                                             const std::string& noise) {
  for (const auto& r : s.method_rows) {
    if (r.method == m && r.vehicle_class == cls && r.cover == cover && r.noise == noise) return &r;
  }
  return nullptr;
}

// The side-by-side tables: overall with time, then per class, cover and noise level, then one
// confusion matrix per method but verify (whose matrix is the one above).
std::string family_methods_markdown(const FamilySummary& s) {
  std::ostringstream md;
  md << "\n### canopy beside the PCL baseline\n\n"
     << "The same candidates (each trial's `samples.pcd`) and the same modelbase: canopy's gmatch rank-1 "
        "model "
        "and verify's class answer; the PCL baseline's (tools/baseline) VFH nearest view and FPFH + RANSAC + "
        "ICP rank-1 model, each answering the class of that model. A failed stage counts as wrong. Time per "
        "trial: wall seconds of the method's own stages after the shared fitvox (gmatch: cocone + ncut + "
        "gmatch; "
        "verify: those + verify; VFH, FPFH: one baseline run each), from the stages' .time files. From "
        "`families/methods.csv` and `families/methods-confusion.csv` (famscore). Rates: k/n with Wilson's "
        "95% interval at the distinct renders (each test vehicle is rendered once per cover level and its "
        "noise levels are noisy copies of that render: a row pooling them has trials / noise levels units; "
        "a row of one noise level, its trials).\n\n"
     << "| method | class accuracy | nearest instance | failed | time per trial (s) |\n"
        "|---|---:|---:|---:|---:|\n";
  const double levels = noise_copies(s);
  for (const auto& m : s.methods) {
    const documents::FamilyMethodRow* r = method_row(s, m, "all", "all", "all");
    std::string t = "–";
    if (r->timed > 0) {
      t = formats::format_number("%.2f", r->seconds_mean);
      if (r->timed < r->trials) t += " (" + std::to_string(r->timed) + " timed)";
    }
    md << "| " << method_label(m) << " | " << rate_ci_units(r->class_right, r->trials, r->trials / levels)
       << " | " << rate_ci_units(r->nearest_right, r->trials, r->trials / levels) << " | " << r->failed
       << " | " << t << " |\n";
  }
  // table(first column, the slices' keys): class accuracy of every method per slice.
  auto table = [&](const std::string& title, const std::vector<std::array<std::string, 3>>& keys,
                   int label_index) {
    md << "\n| " << title << " | trials |";
    for (const auto& m : s.methods) md << " " << method_label(m) << " |";
    md << "\n|---|---:|";
    for (std::size_t k = 0; k < s.methods.size(); ++k) md << "---:|";
    md << "\n";
    for (const auto& key : keys) {
      const documents::FamilyMethodRow* first = method_row(s, s.methods.front(), key[0], key[1], key[2]);
      if (!first) continue;
      md << "| " << key[label_index] << " | " << first->trials << " |";
      for (const auto& m : s.methods) {
        const documents::FamilyMethodRow* r = method_row(s, m, key[0], key[1], key[2]);
        const double units = r ? (label_index == 2 ? r->trials : r->trials / levels) : 0;
        md << " " << (r ? rate_ci_units(r->class_right, r->trials, units) : "–") << " |";
      }
      md << "\n";
    }
  };
  std::vector<std::array<std::string, 3>> classes, covers, noises;
  for (const auto& r : s.method_rows) {
    if (r.method != s.methods.front()) continue;
    if (r.vehicle_class != "all") classes.push_back({r.vehicle_class, "all", "all"});
    if (r.cover != "all") covers.push_back({"all", r.cover, "all"});
    if (r.noise != "all") noises.push_back({"all", "all", r.noise});
  }
  md << "\nClass accuracy per class, per cover level and per noise level:\n";
  table("class", classes, 0);
  table("cover", covers, 1);
  table("noise (mm)", noises, 2);
  for (const auto& mc : s.method_confusion) {
    if (mc.method == "verify") continue;
    md << "\nConfusion matrix of " << method_label(mc.method)
       << " (rows the true class).\n\n| true \\ answered |";
    for (const auto& a : s.method_answers) md << " " << a << " |";
    md << "\n|---|";
    for (std::size_t k = 0; k < s.method_answers.size(); ++k) md << "---:|";
    md << "\n";
    for (const auto& c : mc.classes) {
      md << "| " << c.name << " |";
      for (std::size_t k = 0; k < s.method_answers.size(); ++k) {
        const std::string n = std::to_string(c.answered[k]);
        md << " " << (s.method_answers[k] == c.name && c.answered[k] > 0 ? "**" + n + "**" : n) << " |";
      }
      md << "\n";
    }
  }
  return md.str();
}
}  // namespace

namespace {

// One true class's row: its counts, trials and right answers (the column of its own name).
FamilyClass family_class(const documents::FamilyConfusion::Row& row, const std::vector<std::string>& answers) {
  FamilyClass fc;
  fc.name = row.true_class;
  fc.answered = row.answered;
  for (std::size_t k = 0; k < row.answered.size(); ++k) {
    fc.trials += row.answered[k];
    if (answers[k] == fc.name) fc.right = row.answered[k];
  }
  return fc;
}

// confusion.csv: true_class,<answered classes...> -> the classes and the totals.
void read_confusion(FamilySummary& s, const std::string& confusion, const std::string& confusion_name) {
  const documents::FamilyConfusion c = documents::parse_family_confusion(confusion, confusion_name, false);
  s.answers = c.answers;
  for (const auto& row : c.rows) {
    FamilyClass fc = family_class(row, c.answers);
    s.trials += fc.trials;
    s.right += fc.right;
    s.classes.push_back(std::move(fc));
  }
}

// accuracy.csv: one row per (cover, noise) and the all,all totals, which must agree with the
// confusion matrix's.
void read_levels(FamilySummary& s, const std::string& accuracy, const std::string& accuracy_name,
                 const std::string& confusion_name) {
  bool have_all = false;
  for (const auto& l : documents::parse_family_accuracy(accuracy, accuracy_name)) {
    if (l.cover == "all" && l.noise == "all") {
      s.all = l;
      have_all = true;
    } else {
      s.levels.push_back(l);
    }
  }
  if (!have_all) throw common::DataError(accuracy_name, "no 'all,all' row (the totals)");
  if (s.all.trials != s.trials || s.all.class_right != s.right) {
    throw common::DataError(
        accuracy_name, "its totals (" + std::to_string(s.all.class_right) + " of " +
                           std::to_string(s.all.trials) + " classes right) disagree with " + confusion_name +
                           " (" + std::to_string(s.right) + " of " + std::to_string(s.trials) + ")");
  }
}

// methods.csv and methods-confusion.csv beside accuracy.csv (both or neither).
void read_methods_beside(FamilySummary& s, const std::string& accuracy_name) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(accuracy_name).parent_path();
  const std::string methods = (dir / "methods.csv").string(), mconf = (dir / "methods-confusion.csv").string();
  std::error_code ec;
  const bool has_methods = fs::exists(methods, ec), has_mconf = fs::exists(mconf, ec);
  if (has_methods != has_mconf) {
    throw common::DataError(
        has_methods ? mconf : methods,
        "missing beside " + std::string(has_methods ? methods : mconf) + " (famscore writes both)");
  }
  if (has_methods)
    add_family_methods(s, common::read_file(methods), methods, common::read_file(mconf), mconf);
}

}  // namespace

FamilySummary summarize_families(const std::string& confusion, const std::string& confusion_name,
                                 const std::string& accuracy, const std::string& accuracy_name) {
  FamilySummary s;
  read_confusion(s, confusion, confusion_name);
  read_levels(s, accuracy, accuracy_name, confusion_name);
  read_methods_beside(s, accuracy_name);
  return s;
}

namespace {

// methods.csv's rows, and the methods in first-seen order.
void read_method_rows(const std::string& methods, const std::string& methods_name,
                      std::vector<documents::FamilyMethodRow>& rows, std::vector<std::string>& names) {
  for (const auto& r : documents::parse_family_methods(methods, methods_name)) {
    if (std::find(names.begin(), names.end(), r.method) == names.end()) names.push_back(r.method);
    rows.push_back(r);
  }
}

// Every method has an all,all,all row over the confusion matrix's trials (verify: its right ones too).
void check_method_totals(const FamilySummary& s, const std::vector<documents::FamilyMethodRow>& rows,
                         const std::vector<std::string>& names, const std::string& methods_name) {
  for (const auto& name : names) {
    const auto all = std::find_if(rows.begin(), rows.end(), [&](const documents::FamilyMethodRow& x) {
      return x.method == name && x.vehicle_class == "all" && x.cover == "all" && x.noise == "all";
    });
    if (all == rows.end())
      throw common::DataError(methods_name, "method " + name + " has no all,all,all row");
    if (all->trials != s.trials) {
      throw common::DataError(methods_name, "method " + name + ": " + std::to_string(all->trials) +
                                                " trials, the confusion matrix has " +
                                                std::to_string(s.trials));
    }
    if (name == "verify" && all->class_right != s.right) {
      throw common::DataError(methods_name, "verify: " + std::to_string(all->class_right) +
                                                " classes right, the confusion matrix has " +
                                                std::to_string(s.right));
    }
  }
  if (names.empty()) throw common::DataError(methods_name, "no method (only a header)");
}

// methods-confusion.csv: method,true_class,<answered classes...>, one matrix per method.
std::vector<FamilyMethodConfusion> read_method_confusion(const std::string& confusion,
                                                         const std::string& confusion_name,
                                                         std::vector<std::string>& answers) {
  const documents::FamilyConfusion c = documents::parse_family_confusion(confusion, confusion_name, true);
  std::vector<FamilyMethodConfusion> conf;
  for (const auto& row : c.rows) {
    if (conf.empty() || conf.back().method != row.method) conf.push_back({row.method, {}});
    conf.back().classes.push_back(family_class(row, c.answers));
  }
  answers = c.answers;
  return conf;
}

void check_confusion_agrees(const std::vector<FamilyMethodConfusion>& conf,
                            const std::vector<documents::FamilyMethodRow>& rows,
                            const std::vector<std::string>& names, const std::string& confusion_name,
                            const std::string& methods_name) {
  // Each method's matrix agrees with its rows in methods.csv (trials and right answers per class).
  for (const auto& mc : conf) {
    if (std::find(names.begin(), names.end(), mc.method) == names.end())
      throw common::DataError(confusion_name, "method " + mc.method + " is not in " + methods_name);
    for (const auto& fc : mc.classes) {
      const auto row = std::find_if(rows.begin(), rows.end(), [&](const documents::FamilyMethodRow& x) {
        return x.method == mc.method && x.vehicle_class == fc.name && x.cover == "all" && x.noise == "all";
      });
      if (row == rows.end() || row->trials != fc.trials || row->class_right != fc.right) {
        throw common::DataError(
            confusion_name, "method " + mc.method + ", class " + fc.name + ": " + std::to_string(fc.right) +
                                " of " + std::to_string(fc.trials) + " right disagrees with " + methods_name);
      }
    }
  }
}

}  // namespace

void add_family_methods(FamilySummary& s, const std::string& methods, const std::string& methods_name,
                        const std::string& confusion, const std::string& confusion_name) {
  std::vector<documents::FamilyMethodRow> rows;
  std::vector<std::string> names;
  read_method_rows(methods, methods_name, rows, names);
  check_method_totals(s, rows, names, methods_name);
  std::vector<std::string> answers;
  std::vector<FamilyMethodConfusion> conf = read_method_confusion(confusion, confusion_name, answers);
  check_confusion_agrees(conf, rows, names, confusion_name, methods_name);
  s.methods = names;
  s.method_rows = std::move(rows);
  s.method_answers = std::move(answers);
  s.method_confusion = std::move(conf);
}

std::string families_markdown(const FamilySummary& s) {
  std::ostringstream md;
  // Each test vehicle is rendered once per cover level; its noise levels are copies of that render.
  const double copies = noise_copies(s);
  auto pooled = [&](int k, int n) { return rate_ci_units(k, n, n / copies); };
  md << "\n## Vehicle families (issue 17)\n\n"
     << "The class-level protocol (`make -f Makefile.experiments families`, mk/families.mk, "
        "docs/decisions/families.md): procedural vehicles of "
     << s.classes.size()
     << " classes, tested on instances that are not in the modelbase. The answered class is the class of "
        "verify's best-scoring hypothesis (accepted or not); `none` = no class answered or a stage failed. "
        "From `families/confusion.csv` and `families/accuracy.csv` (famscore). Rates: k/n with Wilson's 95% "
        "interval at the distinct renders (rows pooling the noise levels: trials / noise levels; a row of "
        "one cover and noise level: its trials).\n\n"
     << "**Class accuracy: " << pooled(s.right, s.trials)
     << "**; nearest instance (the modelbase entry of the "
        "true class nearest in size): "
     << pooled(s.all.nearest_right, s.all.trials) << "; verify accepted " << s.all.accepted << " answers, "
     << s.all.accepted_right << " of them of the right class; " << s.all.failed << " failed trials.\n\n";
  md << "| class | trials | class accuracy |\n|---|---:|---:|\n";
  for (const auto& c : s.classes)
    md << "| " << c.name << " | " << c.trials << " | " << pooled(c.right, c.trials) << " |\n";
  md << "| **all** | " << s.trials << " | **" << pooled(s.right, s.trials) << "** |\n\n";
  md << "| cover | noise (mm) | trials | class accuracy | verify accepted (right class) | nearest instance | "
        "failed |\n|---|---:|---:|---:|---:|---:|---:|\n";
  auto level = [&](const documents::FamilyAccuracyRow& l, bool total) {
    const double units = total ? l.trials / copies : l.trials;
    md << "| " << (total ? "**all**" : l.cover) << " | " << (total ? "" : l.noise) << " | " << l.trials << " | "
       << rate_ci_units(l.class_right, l.trials, units) << " | " << l.accepted << " (" << l.accepted_right
       << ") | " << rate_ci_units(l.nearest_right, l.trials, units) << " | " << l.failed << " |\n";
  };
  for (const auto& l : s.levels) level(l, false);
  level(s.all, true);
  md << "\nConfusion matrix: rows the true class, columns the answered class (right answers in bold).\n\n"
     << "| true \\ answered |";
  for (const auto& a : s.answers) md << " " << a << " |";
  md << "\n|---|";
  for (std::size_t k = 0; k < s.answers.size(); ++k) md << "---:|";
  md << "\n";
  for (const auto& c : s.classes) {
    md << "| " << c.name << " |";
    for (std::size_t k = 0; k < s.answers.size(); ++k) {
      const std::string n = std::to_string(c.answered[k]);
      md << " " << (s.answers[k] == c.name && c.answered[k] > 0 ? "**" + n + "**" : n) << " |";
    }
    md << "\n";
  }
  if (!s.methods.empty()) md << family_methods_markdown(s);
  return md.str();
}

}  // namespace canopy::report
