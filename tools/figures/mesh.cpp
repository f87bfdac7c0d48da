// render_mesh: a coloured segmentation mesh, shaded, from a fixed oblique viewpoint.
#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkLightKit.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataNormals.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>
#include <vtkWindowToImageFilter.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "canopy/common/error.h"
#include "canopy/common/math.h"
#include "figures/figures.h"
#include "figures/gl_leaks.h"
#include "figures/vtk_image.h"

namespace canopy::figures {
namespace {

using Vec = std::array<double, 3>;

Vec sub(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec unit(const Vec& a) {
  const double n = std::sqrt(dot(a, a));
  return {a[0] / n, a[1] / n, a[2] / n};
}

std::uint8_t to_byte(double v) {
  if (!(v > 0)) return 0;
  return v >= 255 ? 255 : static_cast<std::uint8_t>(std::lround(v));
}

}  // namespace

namespace detail {

Image capture(vtkRenderWindow* window, const std::string& name) {
  window->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  Image image = from_vtk(grab->GetOutput(), name);
  int* size = window->GetSize();
  if (image.width != size[0] || image.height != size[1]) {
    throw common::Error(name + ": rendered " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                        " pixels instead of " + std::to_string(size[0]) + "x" + std::to_string(size[1]));
  }
  return image;
}

}  // namespace detail

namespace {

// Every face's indices name a vertex; DataError(name) otherwise, and for a mesh without faces.
void check_mesh(const formats::Mesh& mesh, const std::string& name) {
  const auto& v = mesh.vertices;
  v.require({"x", "y", "z"}, name);
  if (mesh.faces.empty()) {
    throw common::DataError(
        name, "mesh has no faces (" + std::to_string(v.size()) + " vertices): nothing to render");
  }
  const std::size_t n = v.size();
  for (const auto& f : mesh.faces) {
    for (const auto i : f) {
      if (i < 0 || static_cast<std::size_t>(i) >= n) {
        throw common::DataError(name, "face index " + std::to_string(i) + " out of range");
      }
    }
  }
}

// Face colour: the colour most of its vertices share (ties: the first vertex).
vtkSmartPointer<vtkUnsignedCharArray> face_colours(const formats::Mesh& mesh, const MeshView& view) {
  const auto& v = mesh.vertices;
  auto colours = vtkSmartPointer<vtkUnsignedCharArray>::New();
  colours->SetName("colour");
  colours->SetNumberOfComponents(3);
  colours->SetNumberOfTuples(static_cast<vtkIdType>(mesh.faces.size()));
  const bool coloured = v.has("red") && v.has("green") && v.has("blue");
  for (std::size_t k = 0; k < mesh.faces.size(); ++k) {
    std::array<std::uint8_t, 3> c = view.default_colour;
    if (coloured) {
      std::array<std::array<std::uint8_t, 3>, 3> vc;
      for (int j = 0; j < 3; ++j) {
        const auto i = static_cast<std::size_t>(mesh.faces[k][j]);
        vc[j] = {to_byte(v.col("red")[i]), to_byte(v.col("green")[i]), to_byte(v.col("blue")[i])};
      }
      c = (vc[1] == vc[2] && vc[0] != vc[1]) ? vc[1] : vc[0];
    }
    colours->SetTypedTuple(static_cast<vtkIdType>(k), c.data());
  }
  return colours;
}

// The mesh as VTK triangles with one colour per face.
vtkSmartPointer<vtkPolyData> poly_data(const formats::Mesh& mesh, const MeshView& view) {
  const auto& v = mesh.vertices;
  const std::size_t n = v.size();
  const auto& X = v.col("x");
  const auto& Y = v.col("y");
  const auto& Z = v.col("z");
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(n));
  for (std::size_t i = 0; i < n; ++i) points->SetPoint(static_cast<vtkIdType>(i), X[i], Y[i], Z[i]);
  vtkNew<vtkCellArray> triangles;
  for (const auto& f : mesh.faces) {
    const vtkIdType ids[3] = {f[0], f[1], f[2]};
    triangles->InsertNextCell(3, ids);
  }
  const auto colours = face_colours(mesh, view);
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetPolys(triangles);
  poly->GetCellData()->SetScalars(colours);
  return poly;
}

// A renderer holding the mesh shaded (smooth normals, direct face colours, light kit).
vtkSmartPointer<vtkRenderer> shaded(vtkPolyData* poly, const MeshView& view) {
  vtkNew<vtkPolyDataNormals> normals;
  normals->SetInputData(poly);
  normals->ComputePointNormalsOn();
  normals->ComputeCellNormalsOff();
  normals->SplittingOff();
  normals->ConsistencyOff();
  normals->AutoOrientNormalsOff();

  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(normals->GetOutputPort());
  mapper->ScalarVisibilityOn();
  mapper->SetScalarModeToUseCellData();
  mapper->SetColorModeToDirectScalars();

  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetInterpolationToGouraud();
  actor->GetProperty()->SetAmbient(0.15);
  actor->GetProperty()->SetDiffuse(0.85);
  actor->GetProperty()->SetSpecular(0.0);

  auto renderer = vtkSmartPointer<vtkRenderer>::New();
  renderer->AddActor(actor);
  renderer->SetBackground(view.background[0] / 255.0, view.background[1] / 255.0, view.background[2] / 255.0);
  renderer->TwoSidedLightingOn();
  renderer->RemoveAllLights();
  vtkNew<vtkLightKit> lights;
  lights->AddLightsToRenderer(renderer);
  return renderer;
}

// Framing box: fixed (same camera for every mesh) or the mesh's bounds.
void framing_box(const formats::Mesh& mesh, const MeshView& view, Vec& lo, Vec& hi) {
  if (view.framing == Framing::kBox) {
    lo = {-view.box[0] / 2, -view.box[1] / 2, 0};
    hi = {view.box[0] / 2, view.box[1] / 2, view.box[2]};
    return;
  }
  const auto& X = mesh.vertices.col("x");
  const auto& Y = mesh.vertices.col("y");
  const auto& Z = mesh.vertices.col("z");
  lo = {std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
        std::numeric_limits<double>::max()};
  hi = {-lo[0], -lo[1], -lo[2]};
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Vec p{X[i], Y[i], Z[i]};
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
  }
}

// A parallel camera looking at the framing box from the view's elevation and azimuth, scaled so
// that the box fills the image (4% margin).
void place_camera(vtkRenderer* renderer, const Vec& lo, const Vec& hi, const MeshView& view) {
  const Vec centre{(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
  const double el = view.elevation_deg * common::kPi / 180, az = view.azimuth_deg * common::kPi / 180;
  const Vec dir{std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
  const Vec up = unit(sub(Vec{0, 0, 1}, Vec{dir[0] * dir[2], dir[1] * dir[2], dir[2] * dir[2]}));
  const Vec right = unit(cross(up, dir));
  double half_w = 0, half_h = 0;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec p{corner & 1 ? hi[0] : lo[0], corner & 2 ? hi[1] : lo[1], corner & 4 ? hi[2] : lo[2]};
    const Vec d = sub(p, centre);
    half_w = std::max(half_w, std::abs(dot(d, right)));
    half_h = std::max(half_h, std::abs(dot(d, up)));
  }
  const double aspect = static_cast<double>(view.width) / view.height;
  const double scale = std::max({half_h, half_w / aspect, 1e-6}) * 1.04;
  const double distance = 10 * std::sqrt(dot(sub(hi, lo), sub(hi, lo))) + 10;
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->ParallelProjectionOn();
  camera->SetFocalPoint(centre[0], centre[1], centre[2]);
  camera->SetPosition(centre[0] + distance * dir[0], centre[1] + distance * dir[1],
                      centre[2] + distance * dir[2]);
  camera->SetViewUp(up[0], up[1], up[2]);
  camera->SetParallelScale(scale);
  renderer->ResetCameraClippingRange();
}

}  // namespace

Image render_mesh(const formats::Mesh& mesh, const MeshView& view, const std::string& name) {
  check_mesh(mesh, name);
  require_display();
  const auto poly = poly_data(mesh, view);
  const auto renderer = shaded(poly, view);
  Vec lo, hi;
  framing_box(mesh, view, lo, hi);
  place_camera(renderer, lo, hi, view);

  const GlLeakScope gl;  // the window and its GL driver (gl_leaks.h)
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);
  window->SetSize(view.width, view.height);
  window->AddRenderer(renderer);
  return detail::capture(window, name);
}

}  // namespace canopy::figures
