// POV-Ray scene text, running POV-Ray in a private directory, decoding its images.
#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <cstring>
#include <map>
#include <sstream>
#include <thread>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/common/math.h"
#include "canopy/formats/labels.h"
#include "rangetrace/rangetrace.h"

namespace canopy::rangetrace {

using common::Error;

namespace {

std::string vec(const Eigen::Vector3d& world) {
  const Eigen::Vector3d p = pov_frame(world);
  char buf[128];
  std::snprintf(buf, sizeof buf, "<%.10g, %.10g, %.10g>", p.x(), p.y(), p.z());
  return buf;
}

std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

// POV-Ray "matrix" of a world-frame affine map: POV-Ray applies p' = p M (row vectors), so
// its rows are the images of the POV-Ray basis vectors.
std::string pov_matrix(const Eigen::Affine3d& world) {
  std::string out = "matrix <";
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d e_pov = Eigen::Vector3d::Unit(i);
    const Eigen::Vector3d image = pov_frame(world.linear() * pov_frame(e_pov));
    out += num(image.x()) + ", " + num(image.y()) + ", " + num(image.z()) + ", ";
  }
  const Eigen::Vector3d t = pov_frame(world.translation());
  return out + num(t.x()) + ", " + num(t.y()) + ", " + num(t.z()) + ">";
}

std::string include_line(const Model& model) {
  if (model.include_dir.empty()) return model.inline_code;
  return "#include \"" + model.include_file + "\"\n";
}

}  // namespace

Placement place(const Eigen::Vector3d& model_min, const Eigen::Vector3d& model_max, const Pose& pose) {
  Placement p;
  p.model_min = model_min;
  p.model_max = model_max;
  const Eigen::Vector3d anchor((model_min.x() + model_max.x()) / 2, (model_min.y() + model_max.y()) / 2,
                               model_min.z());
  p.transform = Eigen::Translation3d(pose.position.x(), pose.position.y(), 0) *
                Eigen::AngleAxisd(pose.heading, Eigen::Vector3d::UnitZ()) * Eigen::Translation3d(-anchor);
  p.top = model_max.z() - model_min.z();
  p.centre = Eigen::Vector3d(pose.position.x(), pose.position.y(), p.top / 2);
  return p;
}

Encoding encoding_for(const Placement& placement, const Params& params) {
  const double c = std::abs(std::cos(params.pose.heading));
  const double s = std::abs(std::sin(params.pose.heading));
  const double margin = 0.25;
  const Eigen::Vector3d half(params.crop_length / 2 * c + params.crop_width / 2 * s + margin,
                             params.crop_length / 2 * s + params.crop_width / 2 * c + margin,
                             params.crop_height / 2 + margin);
  return {placement.centre - half, 2 * half};
}

Eigen::Vector3d view_direction(const View& view, const Pose& pose) {
  const double az = pose.heading + view.azimuth;
  return {std::cos(view.elevation) * std::cos(az), std::cos(view.elevation) * std::sin(az),
          std::sin(view.elevation)};
}

bool in_crop(const Eigen::Vector3d& p, const Placement& placement, const Params& params) {
  const Eigen::Vector3d d = p - placement.centre;
  const double c = std::cos(params.pose.heading), s = std::sin(params.pose.heading);
  const double along = c * d.x() + s * d.y(), across = -s * d.x() + c * d.y();
  return std::abs(along) <= params.crop_length / 2 && std::abs(across) <= params.crop_width / 2 &&
         std::abs(d.z()) <= params.crop_height / 2;
}

PixelWindow crop_window(const Params& params, const View& view, int margin) {
  const int n = params.size;
  const PixelWindow whole{0, n - 1, 0, n - 1};
  // POV-Ray's look_at (POV-Ray frame): direction d toward the target, right = sky x d,
  // up = d x right, both normalised and scaled by the field.
  const Eigen::Vector3d d = -pov_frame(view_direction(view, params.pose)).normalized();
  Eigen::Vector3d right = Eigen::Vector3d::UnitY().cross(d);
  if (right.norm() < 1e-6) return whole;
  right.normalize();
  const Eigen::Vector3d up = d.cross(right).normalized();
  const double field = n * params.spacing;
  const double c = std::cos(params.pose.heading), s = std::sin(params.pose.heading);
  const Eigen::Vector3d along(c, s, 0), across(-s, c, 0), vertical(0, 0, 1);
  double i0 = 1e300, i1 = -1e300, j0 = 1e300, j1 = -1e300;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d corner = (k & 1 ? 0.5 : -0.5) * params.crop_length * along +
                                   (k & 2 ? 0.5 : -0.5) * params.crop_width * across +
                                   (k & 4 ? 0.5 : -0.5) * params.crop_height * vertical;
    const Eigen::Vector3d q = pov_frame(corner);  // relative to the target: the camera's axis
    const double i = (q.dot(right) / field + 0.5) * n - 0.5;
    const double j = (0.5 - q.dot(up) / field) * n - 0.5;
    i0 = std::min(i0, i);
    i1 = std::max(i1, i);
    j0 = std::min(j0, j);
    j1 = std::max(j1, j);
  }
  auto clip = [&](double v) { return static_cast<int>(std::clamp(v, -1.0, double(n))); };
  PixelWindow w{clip(std::floor(i0) - margin), clip(std::ceil(i1) + margin), clip(std::floor(j0) - margin),
                clip(std::ceil(j1) + margin)};
  w.col0 = std::max(w.col0, 0);
  w.row0 = std::max(w.row0, 0);
  w.col1 = std::min(w.col1, n - 1);
  w.row1 = std::min(w.row1, n - 1);
  // The box lies in front of the camera and around its axis: never empty; kept safe anyway.
  if (w.col1 < w.col0 || w.row1 < w.row0) return whole;
  return w;
}

PixelWindow window_union(const std::vector<PixelWindow>& ws) {
  PixelWindow u{std::numeric_limits<int>::max(), -1, std::numeric_limits<int>::max(), -1};
  for (const PixelWindow& w : ws) {
    u = {std::min(u.col0, w.col0), std::max(u.col1, w.col1), std::min(u.row0, w.row0),
         std::max(u.row1, w.row1)};
  }
  return u;
}

std::string scene_pov(const Model& model, const Placement& placement, const Encoding& enc,
                      const std::vector<View>& views, const std::vector<Disc>& foliage, const Params& params,
                      int picture) {
  std::ostringstream s;
  const double field = params.size * params.spacing;
  const double distance = 100.0;  // camera distance from the target (m); orthographic
  s << "// generated by rangetrace\n#version 3.7;\n";
  if (picture == 0) {
    s << "global_settings { assumed_gamma 1.0 ambient_light rgb 0 }\n";
  } else {
    s << "global_settings { assumed_gamma 1.0 ambient_light rgb 1 }\n";
  }
  s << include_line(model) << "\n";
  s << "#declare Target = " << vec(placement.centre) << ";\n";
  s << "#declare Cams = array[" << views.size() << "] {\n";
  for (std::size_t k = 0; k < views.size(); ++k) {
    s << "  " << vec(placement.centre + distance * view_direction(views[k], params.pose))
      << (k + 1 < views.size() ? ",\n" : "\n");
  }
  s << "}\n";
  if (picture == 0) {
    s << "#declare ViewIdx = div(frame_number, 2);\n#declare Pass = mod(frame_number, 2);\n";
    s << "#declare Emit = finish { ambient 0 diffuse 0 specular 0 phong 0 emission 1 }\n";
    s << "#if (Pass = 0)\n  #declare Code = texture { pigment { average pigment_map {\n";
    const char* colours[3] = {"<3, 0, 0>", "<0, 3, 0>", "<0, 0, 3>"};
    for (int axis = 0; axis < 3; ++axis) {
      // World coordinate `axis` of a POV-Ray point p is pov_frame(e_axis) . p.
      const Eigen::Vector3d a = pov_frame(Eigen::Vector3d::Unit(axis));
      s << "    [1 function { min(max((" << num(a.x()) << "*x + " << num(a.y()) << "*y + " << num(a.z())
        << "*z - (" << num(enc.lo[axis]) << ")) / " << num(enc.span[axis])
        << ", 0), 1) } color_map { [0 rgb 0] [1 rgb " << colours[axis] << "] }]\n";
    }
    s << "  } } finish { Emit } }\n";
    s << "  #declare TVehicle = Code;\n  #declare TFoliage = Code;\n  #declare TGround = Code;\n";
    s << "#else\n";
    // Label pass: one full channel per label (formats/labels.h: target, foliage, ground).
    s << "  #declare TVehicle = texture { pigment { rgb <1, 0, 0> } finish { Emit } }\n";
    s << "  #declare TFoliage = texture { pigment { rgb <0, 1, 0> } finish { Emit } }\n";
    s << "  #declare TGround = texture { pigment { rgb <0, 0, 1> } finish { Emit } }\n";
    s << "#end\n";
    s << "camera { orthographic location Cams[ViewIdx] right x*" << num(field) << " up y*" << num(field)
      << " look_at Target }\n";
  } else {
    s << "#declare Shade = finish { ambient 0.25 diffuse 0.75 specular 0.15 roughness 0.05 }\n";
    s << "#declare TVehicle = texture { pigment { rgb <0.62, 0.64, 0.55> } finish { Shade } }\n";
    s << "#declare TFoliage = texture { pigment { rgb <0.18, 0.50, 0.12> } finish { Shade } }\n";
    s << "#declare TGround = texture { pigment { checker rgb <0.55, 0.50, 0.42> rgb <0.50, "
         "0.46, 0.38> scale 1 } finish { ambient 0.3 diffuse 0.7 } }\n";
    const Eigen::Vector3d sun = placement.centre + Eigen::Vector3d(-30, -40, 80);
    s << "light_source { " << vec(sun) << " color rgb 0.9 }\n";
    s << "light_source { " << vec(placement.centre + Eigen::Vector3d(40, 30, 50))
      << " color rgb 0.35 shadowless }\n";
    if (picture == 1) {
      s << "camera { orthographic location Cams[0] right x*" << num(field) << " up y*" << num(field)
        << " look_at Target }\n";
    } else {
      const View oblique{-35 * common::kPi / 180, 25 * common::kPi / 180};
      const double reach = std::max(placement.model_max.x() - placement.model_min.x(),
                                    placement.model_max.y() - placement.model_min.y());
      s << "camera { perspective location "
        << vec(placement.centre + 1.6 * reach * view_direction(oblique, params.pose))
        << " right x up y angle 50 look_at Target }\n";
    }
  }
  s << "background { rgb 0 }\n";
  s << "object { Vehicle " << pov_matrix(placement.transform) << " texture { TVehicle } }\n";
  s << "plane { y, 0 texture { TGround } }\n";
  if (!foliage.empty()) {
    s << "union {\n";
    for (const Disc& d : foliage) {
      s << "  disc { " << vec(d.centre) << ", " << vec(d.normal) << ", " << num(d.radius) << " }\n";
    }
    s << "  texture { TFoliage }\n}\n";
  }
  return s.str();
}

void decode_view(const Image16& coords, const Image16& labels, const Encoding& enc, const Placement& placement,
                 const Params& params, const Eigen::Vector3d& toward, int view_idx, ScanColumns* out) {
  const std::size_t n = static_cast<std::size_t>(coords.width) * coords.height;
  const Eigen::Vector3f sensor = toward.normalized().cast<float>();
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint16_t* c = &coords.rgb[3 * i];
    const std::uint16_t* l = &labels.rgb[3 * i];
    std::uint32_t label = formats::kLabelUnknown;
    if (l[0] > 32767)
      label = formats::kLabelTarget;
    else if (l[1] > 32767)
      label = formats::kLabelFoliage;
    else if (l[2] > 32767)
      label = formats::kLabelGround;
    if (label == formats::kLabelUnknown) continue;  // the ray hit nothing
    bool inside = true;
    Eigen::Vector3d p;
    for (int a = 0; a < 3; ++a) {
      // 0 and 65535 are clamped codes: the hit lies outside the encoded box.
      if (c[a] == 0 || c[a] == 65535) inside = false;
      p[a] = enc.lo[a] + enc.span[a] * (c[a] / 65535.0);
    }
    if (!inside || !in_crop(p, placement, params)) continue;
    out->points.push_back(p.cast<float>());
    out->sensor.push_back(sensor);
    out->view_idx.push_back(view_idx);
    out->label.push_back(label);
  }
}

}  // namespace canopy::rangetrace
