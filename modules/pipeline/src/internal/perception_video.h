// Pictures of one perception frame, for the replay's videos (perception.h): the
// left camera annotated, and the world model from above around the car.
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <array>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "specht/pipeline/stereo_perception.h"
#include "specht/types/track.h"
#include "specht/world/world_model.h"

namespace specht::pipeline::internal {

// RGB of a driving class in every picture: pedestrian red, cyclist yellow, car
// orange, anything else purple.
std::array<unsigned char, 3> ClassColour(const std::string& cls);

// The left image (BGR) with each detection's box in its class's colour, labelled with
// the class, the fused distance (when depth was found) and the id of the track whose
// position is nearest the detection's obstacle (within 2 m, of this frame's stamp).
cv::Mat AnnotatedCamera(const PerceivedFrame& frame, const std::vector<types::Track>& tracks);

// The world model around `car` (extent_m across, north up, size_px square): the cost
// layer (unknown grey, free white, margins shaded, lethal black), the obstacles
// (dots), the tracks (a circle with id and class, the prediction with its 2σ
// ellipses) and the car (a triangle pointing its heading), captioned with `t_s`.
cv::Mat BirdsEye(const world::Snapshot& snapshot, const mrpt::poses::CPose3D& car, double t_s, double extent_m,
                 int size_px);

}  // namespace specht::pipeline::internal
