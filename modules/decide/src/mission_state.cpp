#include "specht/decide/mission_state.h"

#include <array>

namespace specht::decide {

namespace {

using S = MissionState;
using E = MissionEvent;

struct Row {
  S from;
  E event;
  S to;
};

// The header's table, row for row (the "any" rows are handled in NextState).
constexpr std::array<Row, 18> kTable = {{
    {S::kPlan, E::kPathFound, S::kDrive},
    {S::kPlan, E::kNoPath, S::kFailed},
    {S::kDrive, E::kAgentInWay, S::kWait},
    {S::kDrive, E::kGoalReached, S::kPlan},
    {S::kDrive, E::kGoalMissed, S::kPlan},
    {S::kDrive, E::kGoalMissedFinal, S::kFailed},
    {S::kDrive, E::kMissionComplete, S::kDone},
    {S::kWait, E::kWayClear, S::kDrive},
    {S::kWait, E::kPathFound, S::kDrive},
    {S::kDrive, E::kMapChanged, S::kPlan},
    {S::kWait, E::kMapChanged, S::kPlan},
    {S::kEmergencyStop, E::kCollisionCleared, S::kPlan},
    {S::kLocalizationLost, E::kRelocalized, S::kPlan},
    {S::kLocalizationLost, E::kRelocalizationFailed, S::kFailed},
    {S::kBlind, E::kSensorRestored, S::kPlan},
    {S::kPlan, E::kSensorBlind, S::kBlind},
    {S::kDrive, E::kSensorBlind, S::kBlind},
    {S::kWait, E::kSensorBlind, S::kBlind},
}};

}  // namespace

const char* Name(MissionState s) {
  switch (s) {
    case S::kPlan:
      return "plan";
    case S::kDrive:
      return "drive";
    case S::kWait:
      return "wait";
    case S::kEmergencyStop:
      return "emergency_stop";
    case S::kLocalizationLost:
      return "localization_lost";
    case S::kBlind:
      return "blind";
    case S::kDone:
      return "done";
    case S::kFailed:
      return "failed";
  }
  return "?";
}

const char* Name(MissionEvent e) {
  switch (e) {
    case E::kPathFound:
      return "path_found";
    case E::kNoPath:
      return "no_path";
    case E::kAgentInWay:
      return "agent_in_way";
    case E::kWayClear:
      return "way_clear";
    case E::kGoalReached:
      return "goal_reached";
    case E::kGoalMissed:
      return "goal_missed";
    case E::kGoalMissedFinal:
      return "goal_missed_final";
    case E::kMissionComplete:
      return "mission_complete";
    case E::kCollisionImminent:
      return "collision_imminent";
    case E::kCollisionCleared:
      return "collision_cleared";
    case E::kTimeLimit:
      return "time_limit";
    case E::kMapChanged:
      return "map_changed";
    case E::kLocalizationLost:
      return "localization_lost";
    case E::kRelocalized:
      return "relocalized";
    case E::kRelocalizationFailed:
      return "relocalization_failed";
    case E::kSensorBlind:
      return "sensor_blind";
    case E::kSensorRestored:
      return "sensor_restored";
  }
  return "?";
}

MissionState NextState(MissionState state, MissionEvent event) {
  if (state == S::kDone || state == S::kFailed) return state;
  if (event == E::kTimeLimit) return S::kFailed;
  if (state == S::kLocalizationLost && (event == E::kCollisionImminent || event == E::kLocalizationLost)) return state;
  if (event == E::kCollisionImminent) return S::kEmergencyStop;
  if (event == E::kLocalizationLost) return S::kLocalizationLost;
  for (const Row& row : kTable)
    if (row.from == state && row.event == event) return row.to;
  return state;
}

bool MissionStateMachine::Handle(MissionEvent event, double t_s, const std::string& reason) {
  const MissionState next = NextState(state_, event);
  if (next == state_) return false;
  transitions_.push_back({t_s, Name(state_), Name(next), reason});
  state_ = next;
  return true;
}

}  // namespace specht::decide
