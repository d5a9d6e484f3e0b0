// specht/plan/path.h: a planned path — poses of the rear-axle centre, about
// `spacing` apart, each with its driving direction (+1 forward, −1 reverse).
#pragma once

#include <string>
#include <vector>

#include "specht/plan/car.h"

namespace specht::plan {

struct PathPoint {
  Pose pose;
  int direction = 1;
};

struct Path {
  std::vector<PathPoint> points;

  double Length() const;
  int GearChanges() const;
  // Largest turning per metre within a direction: the angle between consecutive
  // chords over their mean length (exact on a circle sampled evenly), 1/m.
  double MaxCurvature() const;
  // CSV: x_m,y_m,theta_rad,direction
  std::string ToCsv() const;
};

}  // namespace specht::plan
