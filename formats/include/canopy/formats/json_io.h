// Forwarding header, kept while other branches still include it: the segment graph is in
// segment_graph.h, the match result in match_result.h. Include those instead.
#pragma once

#include "canopy/formats/match_result.h"
#include "canopy/formats/segment_graph.h"
