// Verdict document of canopy (format "canopy.verdict", version 1): verify's and baseline
// --verdict's model-level answer, and classify's class-level answer ("level": "class", written
// by documents/classification.h). formats/README.md "Verdict". One reader for every tool that
// reads a verdict (collect, report, famscore, the tests): it checks "format" and "version",
// every member it reads and every pose (a rigid transform), and names the file in every error.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "canopy/formats/pose.h"
#include "canopy/formats/provenance.h"

namespace canopy::documents {

using formats::Pose;

inline constexpr const char* kVerdictFormat = "canopy.verdict";
inline constexpr int kVerdictVersion = 1;

// A pose (formats::Pose) is written as {"matrix": the 4 x 4 row-major matrix, 16 numbers,
// "translation", "heading_deg", "pitch_deg", "roll_deg"} (z-y-x Euler angles, degrees).

struct Hypothesis {
  std::string model;
  int gmatch_rank = 0;
  double gmatch_score = 0;
  bool flipped = false;             // the accepted start was the 180-degree flip of its start pose
  std::string start;                // "pairs", "pose", "axes", each also "...-flipped"
  Pose pose;                        // model frame -> candidate frame
  std::optional<Pose> pose_tile;    // model frame -> tile frame, when a transform was given
  double fit_rms = 0;               // m, point-to-plane, over the explained points
  double explained = 0;             // share of the candidate's points on the posed model
  double free_space_violation = 0;  // share of the expected-visible model surface not seen
  double score = 0;                 // explained * (1 - free_space_violation)
  double flip_score = 0;            // best score among the starts flipped against the chosen one
  bool tilted = false;              // no start posed it upright (verify --max-tilt): score 0; written
                                    // only when true
  std::string vehicle_class;        // the model's class ("" = none; written only with has_classes)
};

struct Verdict {
  formats::Provenance provenance;
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
  // verify's null hypothesis (docs/decisions/verify.md §14): a plain box of the candidate's
  // own extent, posed and scored like a model ("box" in the document; absent when verify did
  // not check one, --no-box).
  struct Box {
    double explained = 0, free_space_violation = 0, score = 0;
  };
  std::optional<Box> box;

  // Read, not written by serialize_verdict (it writes the chosen hypothesis's): the top-level
  // "pose" (model or class frame -> candidate frame) and "pose_tile" (-> tile frame).
  std::optional<Pose> pose, pose_tile;
  // classify's class-level answer (docs/decisions/classify.md §9), when the verdict has these
  // members (each optional; "" / nullopt when absent or null).
  std::string level;                                   // "class" for classify's answers
  std::string group;                                   // vehicle group
  std::string reason;                                  // why none: too_sparse, vegetation_like, ...
  std::string detail;                                  // one sentence
  std::string refused_on;                              // what a none rests on: density, surface, size, shape
  std::optional<double> density;                       // object points per m² of its rectangle
  std::optional<double> density_class, density_model;  // "density_needed"
  std::optional<std::array<double, 3>> size;           // L W H (m), >= 0
  std::optional<double> heading_ambiguity;             // degrees (180: front and back unknown)
  // classify's "measured" rectangle (before the sampling correction), whatever the answer:
  // L W H (m), centre in the candidate frame (m), heading (degrees).
  std::optional<std::array<double, 3>> measured_size;
  std::optional<std::array<double, 2>> measured_centre;
  std::optional<double> measured_heading;
  double measured_edge_correction = 0;  // m, added to L and W for the object's extent (0 when absent)
};

// Every error is a common::DataError naming the file and the member ("malformed verdict:
// hypotheses[0].gmatch_rank must be an integer in [1, 2147483647], not 1.5"): integers are
// never cast from other numbers, the candidate is a non-empty path, every model, class, group,
// reason and nearest instance is a name (is_model_name), confidence lies in [0, 1], chosen is
// -1 or a hypothesis index and agrees with model, every pose matrix is 16 numbers with the last
// row 0 0 0 1 and a rotation (orthonormal within 1e-6, determinant +1) as its 3 x 3 part, a
// model (or a class-level class) has a pose, a size is three numbers >= 0.
Verdict read_verdict(const std::string& path);
Verdict parse_verdict(const std::string& text, const std::string& name);

// A model's name as a modelbase spells it (the stem of <name>.json, <name>.pcd): not empty, at
// most 255 bytes, not "." or "..", no '/' and no control character. Anything else would be
// read as a path outside the modelbase or written into documents as such.
bool is_model_name(const std::string& name);
void write_verdict(const Verdict& verdict, const std::string& path);
std::string serialize_verdict(const Verdict& verdict);

}  // namespace canopy::documents
