// specht/decide/mission_state.h: the mission state machine — states, events and
// the transition table, nothing else (no planner, no simulator), so every
// transition can be tested on its own.
//
//   from            event                 to
//   plan            path_found            drive
//   plan            no_path               failed
//   drive           agent_in_way          wait
//   drive           goal_reached          plan       (another goal follows)
//   drive           goal_missed           plan       (a correction from where it stands)
//   drive           goal_missed_final     failed     (no corrections left)
//   drive           mission_complete      done
//   wait            way_clear             drive
//   wait            path_found            drive      (replanned around the agents)
//   drive           map_changed           plan       (the map now blocks the path ahead)
//   wait            map_changed           plan
//   emergency_stop  collision_cleared     plan       (the old path may be stale)
//   localization_lost relocalized         plan       (the path was planned from a wrong pose)
//   localization_lost relocalization_failed failed
//   blind           sensor_restored       plan
//   any but done, failed, localization_lost:
//                   collision_imminent    emergency_stop
//                   localization_lost     localization_lost
//   plan, drive, wait:
//                   sensor_blind          blind
//   any but done, failed:
//                   time_limit            failed
// The emergency stop overrides every other state but a lost localisation: the
// independent collision check raises collision_imminent whatever the machine is
// doing. A lost pose (localisation_lost) stops the car until it is relocalised; the
// emergency stop's way out (collision_cleared → plan) would plan from the wrong pose,
// so it does not take the car out of that state. A blind sensor (perception's frames
// stopped coming) stops the car until they come again. done and failed are final. An event with no row for the current
// state changes nothing (and is not logged).
#pragma once

#include <string>
#include <vector>

namespace specht::decide {

enum class MissionState { kPlan, kDrive, kWait, kEmergencyStop, kLocalizationLost, kBlind, kDone, kFailed };
enum class MissionEvent {
  kPathFound,
  kNoPath,
  kAgentInWay,
  kWayClear,
  kGoalReached,
  kGoalMissed,
  kGoalMissedFinal,
  kMissionComplete,
  kCollisionImminent,
  kCollisionCleared,
  kTimeLimit,
  kMapChanged,
  kLocalizationLost,
  kRelocalized,
  kRelocalizationFailed,
  kSensorBlind,
  kSensorRestored,
};

const char* Name(MissionState state);
const char* Name(MissionEvent event);

struct Transition {
  double t_s = 0;
  std::string from, to, reason;
};

class MissionStateMachine {
 public:
  MissionState state() const { return state_; }
  bool Final() const { return state_ == MissionState::kDone || state_ == MissionState::kFailed; }
  // Applies `event` at time `t_s`: returns whether the state changed (then the
  // transition is logged with `reason`).
  bool Handle(MissionEvent event, double t_s, const std::string& reason);
  const std::vector<Transition>& transitions() const { return transitions_; }

 private:
  MissionState state_ = MissionState::kPlan;
  std::vector<Transition> transitions_;
};

// The table's target for (state, event), or `state` itself when no row applies.
MissionState NextState(MissionState state, MissionEvent event);

}  // namespace specht::decide
