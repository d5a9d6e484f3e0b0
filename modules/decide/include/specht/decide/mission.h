// specht/decide/mission.h: what the car is asked to do, in order — drive to
// waypoints (a pose each) and park in marked bays. A mission file:
//
//   goals:
//     - waypoint: [52, 8, 90]      # x, y, heading in degrees
//     - park: bay-a                # a bay of the scenario, by name
//
// Without a file the mission is to park in the scenario's first bay.
#pragma once

#include <string>
#include <vector>

#include "specht/plan/car.h"

namespace specht::decide {

struct Goal {
  std::string name;   // "waypoint 1", "park bay-a"
  plan::Pose pose;    // the rear-axle reference pose to reach
  bool park = false;  // parking: judged against the bay's tolerances at the end
};

// A marked parking space of the map a mission runs on.
struct Bay {
  std::string name;
  double x_m = 0, y_m = 0, yaw_rad = 0;  // centre, heading along the bay
  double length_m = 5.0, width_m = 2.5;
};

// What a mission file may name: the site's name (for messages) and its bays.
struct MissionSite {
  std::string name;
  std::vector<Bay> bays;
};

// The pose that centres the car's footprint in `bay`, nose along the bay.
plan::Pose BayPose(const Bay& bay, const plan::CarOptions& car);

// Throws InputError naming the file and line: unknown fields, a bay the site
// does not have, a waypoint that is not three numbers.
std::vector<Goal> LoadMission(const std::string& path, const MissionSite& site, const plan::CarOptions& car);
std::vector<Goal> DefaultMission(const MissionSite& site, const plan::CarOptions& car);

}  // namespace specht::decide
