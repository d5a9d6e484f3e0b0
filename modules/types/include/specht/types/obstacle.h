// specht/types/obstacle.h: an obstacle in the map frame, as perception places it and
// the world model keeps it: a detection fused with depth (detect/fusion.h) moved
// from the camera into the map frame, or a simulated detection (sim/detections.h).
#pragma once

#include <opencv2/core.hpp>
#include <string>

#include "specht/core/time.h"

namespace specht::types {

struct Obstacle {
  long id = 0;
  std::string cls;                   // the detector's class name ("pedestrian", "car", …)
  Stamp stamp;                       // when it was seen
  double x_m = 0, y_m = 0, z_m = 0;  // map frame, centre
  double radius_m = 0.5;             // half the larger horizontal extent
  // The oriented box when the sensor measures one (a LiDAR box fit, the simulator):
  // length along yaw_rad, width across it; 0 = only radius_m is known.
  double length_m = 0, width_m = 0, yaw_rad = 0;
  cv::Matx22d covariance_xy = cv::Matx22d::eye() * 0.01;
  double score = 0;
  double range_m = 0;  // distance from the camera along its optical axis (0: unknown)
};

}  // namespace specht::types
