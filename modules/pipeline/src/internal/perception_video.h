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

// `text` in black on a box of `colour`, its baseline at `at`, kept inside the image.
void Label(cv::Mat& image, const std::string& text, cv::Point at, const cv::Scalar& colour, double scale = 0.5);

// The left image (BGR) with each detection's box in its class's colour, labelled with
// the class, the fused distance (when depth was found) and the id of the track whose
// position is nearest the detection's obstacle (within 2 m, of this frame's stamp).
cv::Mat AnnotatedCamera(const PerceivedFrame& frame, const std::vector<types::Track>& tracks);

// The square of the map frame a bird's-eye picture shows.
struct BirdsEyeView {
  double centre_x_m = 0, centre_y_m = 0, extent_m = 40;  // north up, extent_m across
  int size_px = 480;
  static BirdsEyeView Around(const mrpt::poses::CPose3D& car, double extent_m, int size_px);
};

// The world model in `view`: the cost layer (unknown grey, free white, margins
// shaded, lethal black), the obstacles (dots), the tracks in view (a circle with id
// and class, the prediction with its 2σ ellipses), the car (a triangle pointing its
// heading) and the path it follows (map frame, in the car's colour), captioned with
// `t_s`.
cv::Mat BirdsEye(const world::Snapshot& snapshot, const mrpt::poses::CPose3D& car, double t_s, const BirdsEyeView& view,
                 const std::vector<cv::Point2d>& path = {});

}  // namespace specht::pipeline::internal
