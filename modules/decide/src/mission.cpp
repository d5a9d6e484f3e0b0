#include "specht/decide/mission.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>

#include "specht/core/error.h"

namespace specht::decide {

plan::Pose BayPose(const Bay& bay, const plan::CarOptions& car) {
  const double ahead = car.length_m / 2 - car.rear_overhang_m;  // footprint centre ahead of the reference
  return {bay.x_m - ahead * std::cos(bay.yaw_rad), bay.y_m - ahead * std::sin(bay.yaw_rad),
          std::remainder(bay.yaw_rad, 2 * M_PI)};
}

std::vector<Goal> DefaultMission(const MissionSite& s, const plan::CarOptions& car) {
  if (s.bays.empty()) throw InputError(s.name + " has no parking bay: give a mission file");
  return {{"park " + s.bays.front().name, BayPose(s.bays.front(), car), true}};
}

std::vector<Goal> LoadMission(const std::string& path, const MissionSite& s, const plan::CarOptions& car) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw InputError(path + ": cannot open the mission file");
  } catch (const YAML::Exception& e) {
    throw InputError(path + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  const auto at = [&](const YAML::Node& n) { return path + ":" + std::to_string(n.Mark().line + 1) + ": "; };
  if (!root.IsMap() || !root["goals"] || !root["goals"].IsSequence() || root["goals"].size() == 0)
    throw InputError(path + ": a mission is a map with a non-empty 'goals' list");
  // YAML allows a map or a list where a mission has names (keys, a bay).
  const auto name = [&](const YAML::Node& n, const std::string& what) {
    if (!n.IsScalar()) throw InputError(at(n) + what + " is a name, not a map or a list");
    return n.Scalar();
  };
  for (const auto& kv : root)
    if (const std::string field = name(kv.first, "a field"); field != "goals")
      throw InputError(at(kv.first) + "unknown field '" + field + "' (goals)");
  std::vector<Goal> goals;
  int waypoints = 0;
  for (const auto& g : root["goals"]) {
    if (!g.IsMap() || g.size() != 1) throw InputError(at(g) + "a goal is {waypoint: [x, y, deg]} or {park: BAY}");
    const std::string kind = name(g.begin()->first, "a goal's kind");
    const YAML::Node v = g.begin()->second;
    if (kind == "waypoint") {
      std::vector<double> xyz;
      try {
        xyz = v.as<std::vector<double>>();
      } catch (const YAML::Exception&) {
      }
      if (xyz.size() != 3) throw InputError(at(v) + "a waypoint is [x, y, heading_deg]");
      goals.push_back({"waypoint " + std::to_string(++waypoints), {xyz[0], xyz[1], xyz[2] * M_PI / 180}, false});
    } else if (kind == "park") {
      const std::string bay_name = name(v, "a bay");
      const auto bay = std::find_if(s.bays.begin(), s.bays.end(), [&](const auto& b) { return b.name == bay_name; });
      if (bay == s.bays.end()) throw InputError(at(v) + s.name + " has no bay '" + bay_name + "'");
      goals.push_back({"park " + bay_name, BayPose(*bay, car), true});
    } else {
      throw InputError(at(g) + "unknown goal '" + kind + "' (waypoint, park)");
    }
  }
  return goals;
}

}  // namespace specht::decide
