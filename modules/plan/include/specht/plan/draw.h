// specht/plan/draw.h: a picture of a plan — obstacles (black), clearance shading,
// the path (blue forward, red reverse), the car's footprint every `footprint_every_m`
// (grey), start (green) and goal (magenta) footprints. North up, 1 px per map cell
// scaled to at least `min_width_px`.
#pragma once

#include <opencv2/core.hpp>

#include "specht/plan/distance_map.h"
#include "specht/plan/path.h"

namespace specht::plan {

cv::Mat DrawPlan(const DistanceMap& map, const CarOptions& car, const Path& path, const Pose& start, const Pose& goal,
                 double footprint_every_m = 1.5, int min_width_px = 900);

}  // namespace specht::plan
