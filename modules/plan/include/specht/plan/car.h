// specht/plan/car.h: the car the planner plans for — a kinematic bicycle with a
// rectangular footprint. The reference point is the centre of the rear axle
// (where a bicycle model's heading is tangent to the path), so
//   ẋ = v cos θ,  ẏ = v sin θ,  θ̇ = v tan δ / L        (L wheelbase, δ steering)
// and the tightest turn has radius R_min = L / tan δ_max.
//
// The footprint is covered by n discs along the car (n = ⌈length / width⌉), each of
// radius √((length / 2n)² + (width / 2)²): a pose is free when every disc centre is
// farther than its radius + safety margin from the nearest obstacle. The cover is
// conservative (it never accepts a rectangle that touches an obstacle) but
// overshoots the corners; where it says no, the rectangle itself is checked
// (samples over it at the map's resolution, each farther than the margin from an
// obstacle), so tight bays stay reachable.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "specht/core/params.h"

namespace specht::plan {

struct Pose {
  double x = 0, y = 0, theta = 0;  // m, m, rad (rear-axle centre, heading)
};

// The footprint's disc cover, computed once (checks run millions of times).
struct DiscCover {
  std::vector<double> offsets;  // disc centres along the car's axis from the rear axle
  double radius = 0;
  double margin = 0;                           // the safety margin a free pose keeps beyond the footprint
  double front = 0, rear = 0, half_width = 0;  // the rectangle: x in [−rear, front], |y| ≤ half_width
};

// Section "car".
struct CarOptions {
  double wheelbase_m = 1.6;
  double length_m = 2.5;
  double width_m = 1.3;
  double rear_overhang_m = 0.45;  // rear bumper behind the rear axle
  double max_steer_deg = 28.6;
  double max_steer_rate_deg_s = 60.0;
  double max_speed_mps = 5.0;
  double max_reverse_mps = 1.5;
  double max_accel_mps2 = 1.5;
  double safety_margin_m = 0.1;

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Param("wheelbase_m", wheelbase_m, "front to rear axle", Range::Of(0.2, 10.0).Fixed());
    v.Param("length_m", length_m, "footprint length (bumper to bumper)", Range::Of(0.2, 20.0).Fixed());
    v.Param("width_m", width_m, "footprint width", Range::Of(0.1, 5.0).Fixed());
    v.Param("rear_overhang_m", rear_overhang_m, "rear bumper behind the rear axle", Range::Of(0.0, 5.0).Fixed());
    v.Param("max_steer_deg", max_steer_deg, "steering angle limit", Range::Of(1.0, 60.0).Fixed());
    v.Param("max_steer_rate_deg_s", max_steer_rate_deg_s, "steering rate limit", Range::Of(1.0, 1000.0).Fixed());
    v.Param("max_speed_mps", max_speed_mps, "forward speed limit", Range::Of(0.1, 50.0));
    v.Param("max_reverse_mps", max_reverse_mps, "reverse speed limit", Range::Of(0.1, 10.0));
    v.Param("max_accel_mps2", max_accel_mps2, "acceleration and braking limit", Range::Of(0.1, 10.0));
    v.Param("safety_margin_m", safety_margin_m, "clearance kept around the footprint", Range::Of(0.0, 2.0));
  }
  std::vector<std::string> Relations() const;

  double MinTurningRadius() const;
  // Disc centres in the car frame (x forward from the rear axle) and their radius.
  std::vector<cv::Point2d> DiscCentres() const;
  double DiscRadius() const;
  DiscCover Discs() const;
  // The footprint's corners in the map frame at `pose` (for drawing and exact checks).
  std::vector<cv::Point2d> Corners(const Pose& pose) const;
};

}  // namespace specht::plan
