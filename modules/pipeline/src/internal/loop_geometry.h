// Boxes in the plane for the closed loop's checks: the car's footprint, agents and
// perceived tracks as oriented rectangles, and their distances.
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <opencv2/core.hpp>
#include <vector>

#include "specht/plan/car.h"
#include "specht/plan/distance_map.h"
#include "specht/sim/scenario.h"

namespace specht::pipeline::internal {

// A box: centre, heading, half length and half width.
struct Box {
  double x, y, theta, hl, hw;
};

// A planar pose (the simulator's, or a believed one) as MRPT's 3D pose.
inline mrpt::poses::CPose3D Pose3(const sim::Pose2& p) { return {p.x, p.y, 0, p.yaw_rad, 0, 0}; }

// The car's footprint at a rear-axle pose.
Box CarBox(const plan::CarOptions& car, const plan::Pose& p);
std::vector<cv::Point2d> Corners(const Box& b);
// Distance from a point to a box (0 inside).
double PointToBox(const cv::Point2d& p, const Box& b);
// Distance between two boxes (0 when they touch or overlap).
double BoxToBox(const Box& a, const Box& b);
// Smallest obstacle distance along the box's outline (0: touching an obstacle cell).
double OutlineClearance(const plan::DistanceMap& map, const Box& b);

}  // namespace specht::pipeline::internal
