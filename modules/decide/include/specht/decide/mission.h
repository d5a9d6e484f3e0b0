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
#include "specht/sim/scenario.h"

namespace specht::decide {

struct Goal {
  std::string name;  // "waypoint 1", "park bay-a"
  plan::Pose pose;   // the rear-axle reference pose to reach
  bool park = false; // parking: judged against the bay's tolerances at the end
};

// The pose that centres the car's footprint in `bay`, nose along the bay.
plan::Pose BayPose(const sim::ParkingBay& bay, const plan::CarOptions& car);

// Throws InputError naming the file and line: unknown fields, a bay the scenario
// does not have, a waypoint that is not three numbers.
std::vector<Goal> LoadMission(const std::string& path, const sim::Scenario& scenario, const plan::CarOptions& car);
std::vector<Goal> DefaultMission(const sim::Scenario& scenario, const plan::CarOptions& car);

}  // namespace specht::decide
