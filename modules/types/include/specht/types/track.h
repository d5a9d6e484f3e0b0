// specht/types/track.h: a tracked object in the map frame, as the tracker
// (track/tracker.h) estimates it and the online trajectory classifier labels it.
#pragma once

#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "specht/core/time.h"

namespace specht::types {

struct TrackPoint {
  Stamp stamp;
  double x_m = 0, y_m = 0;
};

// Where a track is expected `dt_s` after its stamp, with the position covariance.
struct PredictedPoint {
  double dt_s = 0;
  double x_m = 0, y_m = 0;
  cv::Matx22d covariance = cv::Matx22d::eye();
};

struct Track {
  long id = 0;
  std::string cls;  // the score-weighted vote of its detections' classes
  Stamp stamp;
  double x_m = 0, y_m = 0, vx_mps = 0, vy_mps = 0;
  cv::Matx44d covariance = cv::Matx44d::eye();  // over (x, y, vx, vy)
  // Extent: the latest detection's box (types::Obstacle), length along yaw_rad; 0 =
  // none seen (readers take their class's size).
  double length_m = 0, width_m = 0, yaw_rad = 0;
  std::string state;                                  // "confirmed" or "coasting" (not seen at its stamp)
  std::string motion_model;                           // "cv" or "ct"
  std::vector<TrackPoint> history;                    // filtered positions, oldest first
  std::vector<PredictedPoint> prediction;             // short horizon, for the planner
  std::map<std::string, double> class_probabilities;  // from the trajectory classifier
};

}  // namespace specht::types
