// detect's objects (steps 3 and 4 of detect.h): the points between min_object_height and
// max_height above the DTM, clustered; each cluster tested against the vehicle ranges, split
// where objects only touch, rejected when it is the bottom of something taller.
// docs/decisions/detect.md §3.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "detect/detect.h"
#include "detect/footprint.h"
#include "detect/frame.h"

namespace canopy::detect {

// Planar share and area of an object (shape.h; zero until the shape test ran).
struct Shape {
  double share = 0, area = 0;
};

struct Object {
  std::vector<std::uint32_t> points;  // rows of the tile
  Footprint fp;
  double height = 0;  // highest point above the DTM (m)
  Shape shape;
  bool row_piece = false;   // a piece of a row split or a trim (rows.h): merged only with a tall piece
  bool trim_piece = false;  // a piece of a trim (rows.h): never merged with another
  // The clusters (find_objects' order) the object's points came from: the row and trim rules
  // keep apart only pieces of one cluster (with join_stacked; detect.md §16).
  std::vector<std::size_t> origins;
  // The examinations (Objects::examined) the object came out of: its own and every one above it
  // (the cluster, then the pieces it was split or trimmed into); merged objects: both lists.
  std::vector<std::int32_t> lineage;
};

// One trim to a roof (detect.md §12, §18): the examination of the vehicle's piece and those its
// leftover (the parts cut off it) last held its points in: the rest's own number, then its parts'
// (rest_parts_begin up to rest_parts_end, numbered after the piece's).
struct TrimRest {
  std::int32_t piece = -1, rest = -1, rest_parts_begin = 0, rest_parts_end = 0;
  bool holds(std::int32_t e) const { return e == rest || (e >= rest_parts_begin && e < rest_parts_end); }
};

// The objects that pass the vehicle tests, in the order found, and the counts of the way.
struct Objects {
  std::vector<Object> accepted;
  std::size_t band_points = 0, clusters = 0, splits = 0, row_splits = 0, trims = 0, merges = 0, stacked = 0;
  std::size_t fragments = 0;  // clusters too small alone merged into an object (merge_fragments)
  std::size_t rejected_small = 0, rejected_large = 0, rejected_canopy = 0;
  // Only with Params::object_field (else empty, and no object's lineage is kept): per tile point
  // the last examination (every cluster, piece or part examined gets a number, in order) whose
  // points held it, -1 for none (not in the band). A point whose examination is not in an
  // object's lineage was given by detect to something else (another object, a piece a split or
  // trim cut off, accepted or not): the crops' field `object` (detect.md §17); one a trim cut off
  // the object (`trim_rests`) is its trim's leftover (detect.md §18).
  std::vector<std::int32_t> examined;
  std::vector<TrimRest> trim_rests;  // every trim made, with Params::object_field
};

// `height`: every point's height above the DTM (Ground::height). Throws common::DataError
// naming `name` when the band spans more clustering voxels along an axis than a key holds.
Objects find_objects(const LocalFrame& l, const std::vector<float>& height, const Params& params,
                     const std::string& name);

}  // namespace canopy::detect
