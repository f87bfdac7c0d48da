// Hand-built trials for the report's tests: segments with an area and label, and a trial whose
// correct model has a given rank among two models.
#pragma once

#include <string>
#include <vector>

#include "report/report.h"

namespace canopy::report::testing {

inline documents::Segment seg(int id, double area, int label) {
  documents::Segment s;
  s.segment_id = id;
  s.area = area;
  s.label = label;
  return s;
}

// The correct model scores 0.9 at rank 1 or 0.4 at rank `rank` (the other model 0.4 or 0.9 at
// rank 1); the scores' entropy is 0.5.
inline Case trial(const std::string& object, const std::string& scene, int noise, int rank) {
  Case c;
  c.object = object;
  c.scene = scene;
  c.noise_mm = noise;
  documents::ModelScore right, wrong;  // error terms 0, no pairs
  right.model = object;
  right.score = rank == 1 ? 0.9 : 0.4;
  right.rank = rank;
  wrong.model = "other";
  wrong.score = rank == 1 ? 0.4 : 0.9;
  wrong.rank = rank == 1 ? 2 : 1;
  c.match.models = rank == 1 ? std::vector<documents::ModelScore>{right, wrong}
                             : std::vector<documents::ModelScore>{wrong, right};
  c.match.entropy = 0.5;
  return c;
}

}  // namespace canopy::report::testing
