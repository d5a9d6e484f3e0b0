// specht/sim/world.h: the static world as line segments, ray casting against it (and
// against moving boxes), and its true occupancy grid.
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>

#include <vector>

#include "specht/sim/scenario.h"

namespace specht::sim {

struct Segment {
  Vec2 a, b;
};

// The outline of a w × l box centred at `pose`, long side along its heading.
std::vector<Segment> BoxOutline(const Pose2& pose, double length_m, double width_m);

class World {
 public:
  explicit World(const Scenario& scenario);

  // Distance from `origin` along `angle` to the first segment of the world or of
  // `moving`, or +inf when nothing is hit within max_range_m. *hit_moving tells
  // whether the hit was a moving box (may be null).
  //   ray p + t·d, segment a + u·(b − a):  t = ((a − p) × e) / (d × e),
  //   u = ((a − p) × d) / (d × e), e = b − a; a hit needs t ≥ 0 and 0 ≤ u ≤ 1.
  double RayCast(Vec2 origin, double angle, double max_range_m, const std::vector<Segment>& moving,
                 bool* hit_moving = nullptr) const;

  // The true occupancy grid: object outlines and the inside of closed objects are
  // occupied, everything else within the bounds free.
  mrpt::maps::COccupancyGridMap2D TrueGrid(double resolution_m) const;

  // Whether a point lies inside a closed object or outside the bounds.
  bool Blocked(Vec2 p) const;

  const std::vector<Segment>& segments() const { return segments_; }

 private:
  const Scenario& scenario_;
  std::vector<Segment> segments_;
};

}  // namespace specht::sim
