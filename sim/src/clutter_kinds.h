// The clutter kinds added for issue 29's "unseen clutter" (clutter_kinds.cpp): objects that no
// threshold of verify or classify was fitted on. Each mesh is in its local frame (x along its
// length, z up, the ground at z = 0, centred on the origin in x and y) with its dimensions drawn
// from `rng` within the bounds share/scenes/README.md documents. Private to sim/.
#pragma once

#include "canopy/common/rng.h"
#include "canopy/sim/tile.h"

namespace canopy::sim {

// A unit icosphere subdivided `levels` times (boulder and rock).
TriMesh icosphere(int levels);

TriMesh trailer_mesh(common::Rng& rng);
TriMesh caravan_mesh(common::Rng& rng);
TriMesh pipes_mesh(common::Rng& rng);
TriMesh barriers_mesh(common::Rng& rng);
TriMesh tent_mesh(common::Rng& rng);
TriMesh rock_mesh(common::Rng& rng);

}  // namespace canopy::sim
