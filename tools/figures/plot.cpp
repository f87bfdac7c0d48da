// parse_scores_csv and plot_scores (vtkChartMatrix of vtkChartXY, one chart per scene).
#include <vtkAxis.h>
#include <vtkChart.h>
#include <vtkChartLegend.h>
#include <vtkChartMatrix.h>
#include <vtkChartXY.h>
#include <vtkContextScene.h>
#include <vtkContextActor.h>
#include <vtkDoubleArray.h>
#include <vtkFloatArray.h>
#include <vtkNew.h>
#include <vtkPen.h>
#include <vtkPlot.h>
#include <vtkPlotPoints.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>
#include <vtkVector.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <sstream>

#include "canopy/common/error.h"
#include "figures/figures.h"
#include "figures/gl_leaks.h"
#include "figures/vtk_image.h"

namespace canopy::figures {
namespace {

std::string trim(const std::string& s) {
  std::size_t b = 0, e = s.size();
  while (b < e && (s[b] == ' ' || s[b] == '\t' || s[b] == '\r')) ++b;
  while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\t' || s[e - 1] == '\r')) --e;
  std::string t = s.substr(b, e - b);
  if (t.size() >= 2 && t.front() == '"' && t.back() == '"') t = t.substr(1, t.size() - 2);
  return t;
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::string field;
  bool quoted = false;
  for (char c : line) {
    if (c == '"') quoted = !quoted;
    if (c == ',' && !quoted) {
      out.push_back(trim(field));
      field.clear();
    } else {
      field += c;
    }
  }
  out.push_back(trim(field));
  return out;
}

bool missing(const std::string& s) {
  std::string l = s;
  std::transform(l.begin(), l.end(), l.begin(), [](unsigned char c) { return std::tolower(c); });
  return l.empty() || l == "nan" || l == "na" || l == "-";
}

double number(const std::string& s, const std::string& name, int line, const std::string& column) {
  if (missing(s)) return std::numeric_limits<double>::quiet_NaN();
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(s, &used);
  } catch (const std::exception&) { used = 0; }
  if (used != s.size()) {
    throw common::DataError(name,
                            "line " + std::to_string(line) + ": " + column + " '" + s + "' is not a number");
  }
  return v;
}

// Distinct colours for the first series: ColorBrewer Dark2, then two of Set1 (the thesis's five
// objects use the first five), then six more picked for distance from these (pairwise RGB
// distance >= 60) and from the white background and the black failure crosses.
const unsigned char kPalette[][3] = {{27, 158, 119},  {217, 95, 2},   {117, 112, 179}, {231, 41, 138},
                                     {102, 166, 30},  {230, 171, 2},  {166, 118, 29},  {102, 102, 102},
                                     {228, 26, 28},   {55, 126, 184}, {0, 0, 128},     {100, 30, 20},
                                     {247, 129, 191}, {240, 50, 230}, {23, 190, 207},  {0, 100, 0}};

}  // namespace

std::array<std::uint8_t, 3> series_colour(std::size_t i) {
  constexpr std::size_t n = sizeof kPalette / sizeof kPalette[0];
  if (i < n) return {kPalette[i][0], kPalette[i][1], kPalette[i][2]};
  // Beyond the table: hues a golden angle apart, alternating two saturation/value levels.
  const double h = std::fmod(static_cast<double>(i - n) * 137.50776405, 360.0) / 60.0;
  const double v = (i - n) % 2 == 0 ? 0.80 : 0.55, sat = 0.85;
  const double c = v * sat, x = c * (1 - std::fabs(std::fmod(h, 2.0) - 1)), m = v - c;
  double r = 0, g = 0, b = 0;
  switch (static_cast<int>(h)) {
    case 0: r = c, g = x; break;
    case 1: r = x, g = c; break;
    case 2: g = c, b = x; break;
    case 3: g = x, b = c; break;
    case 4: r = x, b = c; break;
    default: r = c, b = x; break;
  }
  auto byte = [&](double u) { return static_cast<std::uint8_t>(std::lround(255 * (u + m))); };
  return {byte(r), byte(g), byte(b)};
}

std::vector<ScoreRow> parse_scores_csv(const std::string& text, const std::string& name,
                                       const PlotColumns& columns) {
  std::istringstream in(text);
  std::string line;
  int number_of_line = 0;
  std::map<std::string, std::size_t> column;
  std::vector<ScoreRow> rows;
  while (std::getline(in, line)) {
    ++number_of_line;
    if (trim(line).empty() || trim(line)[0] == '#') continue;
    const auto fields = split(line);
    if (column.empty()) {
      for (std::size_t i = 0; i < fields.size(); ++i) column.emplace(fields[i], i);
      for (const std::string& need :
           {columns.series, columns.panel, columns.x, columns.y, columns.lo, columns.hi}) {
        if (!need.empty() && !column.count(need)) {
          throw common::DataError(
              name, "header lacks the column '" + need + "'" +
                        (columns.strict ? " (want object,scene,noise_mm,score,rank,entropy)" : ""));
        }
      }
      continue;
    }
    auto get = [&](const std::string& key) -> std::string {
      const auto it = column.find(key);
      if (it == column.end()) return "";
      if (it->second >= fields.size()) {
        throw common::DataError(name, "line " + std::to_string(number_of_line) + ": " +
                                          std::to_string(fields.size()) + " fields, no '" + key + "'");
      }
      return fields[it->second];
    };
    ScoreRow r;
    r.object = get(columns.series);
    r.scene = columns.panel.empty() ? "" : get(columns.panel);
    if (r.object.empty() || (!columns.panel.empty() && r.scene.empty())) {
      throw common::DataError(name, "line " + std::to_string(number_of_line) + ": empty " + columns.series +
                                        (columns.panel.empty() ? "" : " or " + columns.panel));
    }
    const std::string x = get(columns.x);
    if (!columns.strict && !missing(x)) {
      std::size_t used = 0;
      try {
        std::stod(x, &used);
      } catch (const std::exception&) { used = 0; }
      if (used != x.size()) continue;  // a summary row ("all")
    }
    r.noise_mm = number(x, name, number_of_line, columns.x);
    if (!std::isfinite(r.noise_mm)) {
      throw common::DataError(name, "line " + std::to_string(number_of_line) + ": " + columns.x + " missing");
    }
    r.score = number(get(columns.y), name, number_of_line, columns.y);
    const double rank = number(get("rank"), name, number_of_line, "rank");
    r.rank = std::isfinite(rank) ? static_cast<int>(std::lround(rank)) : 0;
    r.entropy = number(get("entropy"), name, number_of_line, "entropy");
    if (!columns.lo.empty()) r.lo = number(get(columns.lo), name, number_of_line, columns.lo);
    if (!columns.hi.empty()) r.hi = number(get(columns.hi), name, number_of_line, columns.hi);
    rows.push_back(r);
  }
  if (column.empty()) throw common::DataError(name, "empty file: no header line");
  return rows;
}

namespace {

// Axes of the figure, in order of first appearance (noise levels sorted).
struct Axes {
  std::vector<std::string> scenes, objects;
  std::vector<double> levels;
  double top = 1, bottom = 0;
};

Axes axes_of(const std::vector<ScoreRow>& rows, const std::string& name) {
  Axes a;
  bool any = false;
  for (const auto& r : rows) {
    if (!std::isfinite(r.score)) continue;
    any = true;
    if (std::find(a.scenes.begin(), a.scenes.end(), r.scene) == a.scenes.end()) a.scenes.push_back(r.scene);
    if (std::find(a.objects.begin(), a.objects.end(), r.object) == a.objects.end())
      a.objects.push_back(r.object);
    if (std::find(a.levels.begin(), a.levels.end(), r.noise_mm) == a.levels.end())
      a.levels.push_back(r.noise_mm);
    a.top = std::max({a.top, r.score, std::isfinite(r.hi) ? r.hi : r.score});
    a.bottom = std::min({a.bottom, r.score, std::isfinite(r.lo) ? r.lo : r.score});
  }
  if (!any) throw common::DataError(name, "no row has a score: nothing to plot");
  std::sort(a.levels.begin(), a.levels.end());
  return a;
}

// The chart's title and axes: x the noise levels at equal spacing, y bottom..top (+2%).
void set_axes(vtkChartXY* chart, const PlotParams& params, const std::string& scene, const Axes& a,
              vtkDoubleArray* ticks, vtkStringArray* tick_labels) {
  chart->SetTitle(params.title.empty() ? "scene: " + scene
                  : scene.empty()      ? params.title
                                       : params.title + ": " + scene);
  chart->GetTitleProperties()->SetFontSize(16);
  chart->GetTitleProperties()->SetBold(true);
  vtkAxis* x = chart->GetAxis(vtkAxis::BOTTOM);
  x->SetTitle(params.x_title.c_str());
  x->SetBehavior(vtkAxis::FIXED);
  x->SetRange(-0.25, static_cast<double>(a.levels.size()) - 0.75);
  x->SetCustomTickPositions(ticks, tick_labels);
  x->SetGridVisible(false);
  vtkAxis* y = chart->GetAxis(vtkAxis::LEFT);
  y->SetTitle(params.y_title.c_str());
  y->SetBehavior(vtkAxis::FIXED);
  y->SetRange(a.bottom, a.top * 1.02);
}

// A table of two float columns named x_name and y_name holding the points, in order.
vtkSmartPointer<vtkTable> xy_table(const char* x_name, const std::string& y_name,
                                   const std::vector<std::pair<float, float>>& points) {
  auto table = vtkSmartPointer<vtkTable>::New();
  vtkNew<vtkFloatArray> px, py;
  px->SetName(x_name);
  py->SetName(y_name.c_str());
  table->AddColumn(px);
  table->AddColumn(py);
  table->SetNumberOfRows(static_cast<vtkIdType>(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i) {
    table->SetValue(static_cast<vtkIdType>(i), 0, points[i].first);
    table->SetValue(static_cast<vtkIdType>(i), 1, points[i].second);
  }
  return table;
}

// The line of object o in one scene (points by x); its rank > 1 points go to fx, fy.
void add_line(vtkChartXY* chart, const std::vector<ScoreRow>& rows, const std::string& scene, const Axes& a,
              std::size_t o, vtkFloatArray* fx, vtkFloatArray* fy) {
  auto position = [&](double noise) {
    return static_cast<float>(std::find(a.levels.begin(), a.levels.end(), noise) - a.levels.begin());
  };
  std::vector<std::pair<float, float>> points;
  for (const auto& r : rows) {
    if (r.scene != scene || r.object != a.objects[o] || !std::isfinite(r.score)) continue;
    points.emplace_back(position(r.noise_mm), static_cast<float>(r.score));
    if (r.rank > 1) {
      fx->InsertNextValue(points.back().first);
      fy->InsertNextValue(points.back().second);
    }
  }
  if (points.empty()) return;
  std::stable_sort(points.begin(), points.end(),
                   [](const auto& p, const auto& q) { return p.first < q.first; });
  const vtkSmartPointer<vtkTable> table = xy_table("noise", a.objects[o], points);
  const auto c = series_colour(o);
  // The intervals: a thin vertical bar per point, beside its line's point (offset by the
  // series so that bars of one level do not hide each other), left out of the legend.
  for (const auto& r : rows) {
    if (r.scene != scene || r.object != a.objects[o] || !std::isfinite(r.lo) || !std::isfinite(r.hi))
      continue;
    const float bx = position(r.noise_mm) + 0.04f * (static_cast<float>(o) - 0.5f * (a.objects.size() - 1.0f));
    const vtkSmartPointer<vtkTable> bar =
        xy_table("x", "interval", {{bx, static_cast<float>(r.lo)}, {bx, static_cast<float>(r.hi)}});
    vtkPlot* b = chart->AddPlot(vtkChart::LINE);
    b->SetInputData(bar, 0, 1);
    b->SetColor(c[0], c[1], c[2], 255);
    b->SetWidth(1.5);
    b->SetLegendVisibility(false);
    if (auto* bp = vtkPlotPoints::SafeDownCast(b)) bp->SetMarkerStyle(vtkPlotPoints::NONE);
  }
  vtkPlot* line = chart->AddPlot(vtkChart::LINE);
  line->SetInputData(table, 0, 1);
  line->SetColor(c[0], c[1], c[2], 255);
  line->SetWidth(2.5);
  line->SetLabel(a.objects[o]);
  if (auto* pp = vtkPlotPoints::SafeDownCast(line)) {
    pp->SetMarkerStyle(vtkPlotPoints::CIRCLE);
    pp->SetMarkerSize(7);
  }
}

// One panel: its axes, a line per object, black crosses where the correct model is not first.
void fill_chart(vtkChartXY* chart, const std::vector<ScoreRow>& rows, const PlotParams& params, const Axes& a,
                std::size_t s, vtkDoubleArray* ticks, vtkStringArray* tick_labels) {
  set_axes(chart, params, a.scenes[s], a, ticks, tick_labels);
  vtkNew<vtkTable> failures_table;
  vtkNew<vtkFloatArray> fx, fy;
  fx->SetName("noise");
  fy->SetName("rank > 1");
  failures_table->AddColumn(fx);
  failures_table->AddColumn(fy);
  for (std::size_t o = 0; o < a.objects.size(); ++o) add_line(chart, rows, a.scenes[s], a, o, fx, fy);
  if (fx->GetNumberOfTuples() > 0) {
    vtkPlot* marks = chart->AddPlot(vtkChart::POINTS);
    marks->SetInputData(failures_table, 0, 1);
    marks->SetColor(0, 0, 0, 255);
    marks->SetLabel("not rank 1");
    if (auto* pp = vtkPlotPoints::SafeDownCast(marks)) {
      pp->SetMarkerStyle(vtkPlotPoints::CROSS);
      pp->SetMarkerSize(14);
    }
  }
  // One legend (colours are the same in every panel), bottom left: scores start high at
  // low noise, so that corner is usually empty.
  chart->SetShowLegend(s == 0);
  chart->GetLegend()->SetHorizontalAlignment(vtkChartLegend::LEFT);
  chart->GetLegend()->SetVerticalAlignment(vtkChartLegend::BOTTOM);
}

}  // namespace

Image plot_scores(const std::vector<ScoreRow>& rows, const PlotParams& params, const std::string& name) {
  const Axes a = axes_of(rows, name);
  require_display();

  // A context scene in a plain render window. (vtkContextView would also create an X
  // interactor, whose Initialize() in Render() crashed in XSync in 3 of 20 runs under Xvfb.)
  const GlLeakScope gl;  // the window and its GL driver (gl_leaks.h)
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);
  window->SetSize(params.width, params.height);
  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(1, 1, 1);
  window->AddRenderer(renderer);
  vtkNew<vtkContextActor> context;
  renderer->AddActor(context);
  vtkContextScene* scene = context->GetScene();
  scene->SetRenderer(renderer);
  vtkNew<vtkChartMatrix> matrix;
  matrix->SetSize(vtkVector2i(static_cast<int>(a.scenes.size()), 1));
  matrix->SetGutter(vtkVector2f(30, 30));
  matrix->SetBorders(40, 40, 20, 20);
  scene->AddItem(matrix);

  vtkNew<vtkDoubleArray> ticks;
  vtkNew<vtkStringArray> tick_labels;
  for (std::size_t i = 0; i < a.levels.size(); ++i) {
    ticks->InsertNextValue(static_cast<double>(i));
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", a.levels[i]);
    tick_labels->InsertNextValue(buf);
  }
  for (std::size_t s = 0; s < a.scenes.size(); ++s) {
    auto* chart = vtkChartXY::SafeDownCast(matrix->GetChart(vtkVector2i(static_cast<int>(s), 0)));
    if (chart == nullptr) throw common::Error("VTK chart matrix did not create an XY chart");
    fill_chart(chart, rows, params, a, s, ticks, tick_labels);
  }
  return detail::capture(window, name);
}

}  // namespace canopy::figures
