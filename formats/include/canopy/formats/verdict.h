// Verdict document of canopy (format "canopy.verdict", version 1), written by `verify`.
// See formats/README.md. The reader checks "format" and "version" and names the file in every
// error.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "canopy/formats/provenance.h"

namespace canopy::formats {

// A rigid pose: p_to = rotation * p_from + translation. Written as the 4 x 4 row-major matrix
// plus heading/pitch/roll (z-y-x Euler angles, degrees) and the translation (m), float64.
struct Pose {
  std::array<double, 9> rotation{1, 0, 0, 0, 1, 0, 0, 0, 1};  // row-major
  std::array<double, 3> translation{};
};

struct Hypothesis {
  std::string model;
  int gmatch_rank = 0;
  double gmatch_score = 0;
  bool flipped = false;             // the accepted start was the 180-degree flip of the pairs' pose
  std::string start;                // "pairs", "pairs-flipped", "axes", "axes-flipped"
  Pose pose;                        // model frame -> candidate frame
  std::optional<Pose> pose_tile;    // model frame -> tile frame, when a transform was given
  double fit_rms = 0;               // m, point-to-plane, over the explained points
  double explained = 0;             // share of the candidate's points on the posed model
  double free_space_violation = 0;  // share of the expected-visible model surface not seen
  double score = 0;                 // explained * (1 - free_space_violation)
  double flip_score = 0;            // best score among the starts flipped against the chosen one
  std::string vehicle_class;        // the model's class ("" = none; written only with has_classes)
};

struct Verdict {
  Provenance provenance;
  std::string candidate;               // points path, as given
  std::string model;                   // "" = none
  double confidence = 0;               // in [0, 1]: probability that `model` is right (or, for none,
                                       // that no hypothesis was right)
  std::optional<Pose> transform;       // candidate frame -> tile frame, when given
  std::vector<Hypothesis> hypotheses;  // in gmatch rank order
  int chosen = -1;                     // index into hypotheses, -1 = none
  // Class answer, present when the modelbase carries classes (<model>.class files): the class
  // and name of the best-scoring hypothesis whether or not it passed the acceptance threshold,
  // its score and its margin over the best hypothesis of another class (0 when none).
  bool has_classes = false;
  std::string vehicle_class;  // "" = none (no hypothesis, or its model has no class)
  std::string nearest_instance;
  double class_score = 0, class_margin = 0;
};

// Heading, pitch, roll in degrees of a rotation (R = Rz(heading) Ry(pitch) Rx(roll)).
std::array<double, 3> euler_degrees(const Pose& pose);

// Every error is a common::DataError naming the file and the member ("malformed verdict:
// hypotheses[0].gmatch_rank must be an integer in [1, 2147483647], not 1.5"): integers are
// never cast from other numbers, every model, class and nearest instance is a name
// (is_model_name), chosen is -1 or a hypothesis index and agrees with model.
Verdict read_verdict(const std::string& path);
Verdict parse_verdict(const std::string& text, const std::string& name);

// A model's name as a modelbase spells it (the stem of <name>.json, <name>.pcd): not empty, at
// most 255 bytes, not "." or "..", no '/' and no control character. Anything else would be
// read as a path outside the modelbase or written into documents as such.
bool is_model_name(const std::string& name);
void write_verdict(const Verdict& verdict, const std::string& path);
std::string serialize_verdict(const Verdict& verdict);

}  // namespace canopy::formats
