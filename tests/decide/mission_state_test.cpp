// The mission state machine, transition by transition: every (state, event) pair
// against the table of mission_state.h — the expected next state is written out
// here independently, so a changed row fails; the emergency stop overrides every
// state but the final ones and a lost localisation; a lost localisation stops the
// car until it is relocalised; final states absorb everything; only changes are
// logged.
#include "specht/decide/mission_state.h"

#include <gtest/gtest.h>

#include <map>
#include <utility>

namespace specht::decide {
namespace {

using S = MissionState;
using E = MissionEvent;

const std::vector<S> kStates = {S::kPlan,  S::kDrive, S::kWait,  S::kEmergencyStop, S::kLocalizationLost,
                                S::kBlind, S::kDone,  S::kFailed};
const std::vector<E> kEvents = {
    E::kPathFound,   E::kNoPath,          E::kAgentInWay,       E::kWayClear,          E::kGoalReached,
    E::kGoalMissed,  E::kGoalMissedFinal, E::kMissionComplete,  E::kCollisionImminent, E::kCollisionCleared,
    E::kTimeLimit,   E::kMapChanged,      E::kLocalizationLost, E::kRelocalized,       E::kRelocalizationFailed,
    E::kSensorBlind, E::kSensorRestored};

// Events → states, the table as the header documents it; pairs not listed keep
// their state.
const std::map<std::pair<S, E>, S> kExpected = {
    {{S::kPlan, E::kPathFound}, S::kDrive},
    {{S::kPlan, E::kNoPath}, S::kFailed},
    {{S::kDrive, E::kAgentInWay}, S::kWait},
    {{S::kDrive, E::kGoalReached}, S::kPlan},
    {{S::kDrive, E::kGoalMissed}, S::kPlan},
    {{S::kDrive, E::kGoalMissedFinal}, S::kFailed},
    {{S::kDrive, E::kMissionComplete}, S::kDone},
    {{S::kWait, E::kWayClear}, S::kDrive},
    {{S::kWait, E::kPathFound}, S::kDrive},
    {{S::kDrive, E::kMapChanged}, S::kPlan},
    {{S::kWait, E::kMapChanged}, S::kPlan},
    {{S::kEmergencyStop, E::kCollisionCleared}, S::kPlan},
    {{S::kLocalizationLost, E::kRelocalized}, S::kPlan},
    {{S::kLocalizationLost, E::kRelocalizationFailed}, S::kFailed},
    {{S::kBlind, E::kSensorRestored}, S::kPlan},
    {{S::kPlan, E::kSensorBlind}, S::kBlind},
    {{S::kDrive, E::kSensorBlind}, S::kBlind},
    {{S::kWait, E::kSensorBlind}, S::kBlind},
    // the emergency stop, from every state that is not final but a lost localisation
    {{S::kPlan, E::kCollisionImminent}, S::kEmergencyStop},
    {{S::kDrive, E::kCollisionImminent}, S::kEmergencyStop},
    {{S::kWait, E::kCollisionImminent}, S::kEmergencyStop},
    {{S::kBlind, E::kCollisionImminent}, S::kEmergencyStop},
    // a lost localisation, from every state that is not final
    {{S::kPlan, E::kLocalizationLost}, S::kLocalizationLost},
    {{S::kDrive, E::kLocalizationLost}, S::kLocalizationLost},
    {{S::kWait, E::kLocalizationLost}, S::kLocalizationLost},
    {{S::kEmergencyStop, E::kLocalizationLost}, S::kLocalizationLost},
    {{S::kBlind, E::kLocalizationLost}, S::kLocalizationLost},
    // the time limit, from every state that is not final
    {{S::kPlan, E::kTimeLimit}, S::kFailed},
    {{S::kDrive, E::kTimeLimit}, S::kFailed},
    {{S::kWait, E::kTimeLimit}, S::kFailed},
    {{S::kEmergencyStop, E::kTimeLimit}, S::kFailed},
    {{S::kLocalizationLost, E::kTimeLimit}, S::kFailed},
    {{S::kBlind, E::kTimeLimit}, S::kFailed},
};

TEST(MissionStateTest, EveryStateAndEventFollowsTheTable) {
  for (const S s : kStates)
    for (const E e : kEvents) {
      const auto row = kExpected.find({s, e});
      const S expected = row == kExpected.end() ? s : row->second;
      EXPECT_EQ(NextState(s, e), expected)
          << Name(s) << " + " << Name(e) << " → " << Name(NextState(s, e)) << ", expected " << Name(expected);
    }
}

TEST(MissionStateTest, EmergencyStopOverridesEveryStateButTheFinalOnesAndALostPose) {
  for (const S s : kStates) {
    const bool keeps = s == S::kDone || s == S::kFailed || s == S::kLocalizationLost;
    EXPECT_EQ(NextState(s, E::kCollisionImminent), keeps ? s : S::kEmergencyStop) << Name(s);
  }
  // In the emergency stop nothing but the all-clear, a lost pose or the time limit moves on.
  for (const E e : kEvents) {
    if (e == E::kCollisionCleared || e == E::kTimeLimit || e == E::kLocalizationLost) continue;
    EXPECT_EQ(NextState(S::kEmergencyStop, e), S::kEmergencyStop) << Name(e);
  }
}

TEST(MissionStateTest, ALostPoseStopsTheCarUntilRelocalised) {
  MissionStateMachine m;
  EXPECT_TRUE(m.Handle(E::kPathFound, 0.0, "path to bay-a"));
  EXPECT_TRUE(m.Handle(E::kLocalizationLost, 3.0, "5 scans in a row disagree with the map"));
  // The emergency stop's all-clear would replan from the wrong pose: neither moves it.
  EXPECT_FALSE(m.Handle(E::kCollisionImminent, 3.1, "a LiDAR return within the stopping distance"));
  EXPECT_FALSE(m.Handle(E::kCollisionCleared, 4.2, "clear"));
  EXPECT_FALSE(m.Handle(E::kPathFound, 4.3, "a stale plan"));
  EXPECT_EQ(m.state(), S::kLocalizationLost);
  EXPECT_TRUE(m.Handle(E::kRelocalized, 5.0, "relocalised 2.1 m, 19° away"));
  EXPECT_EQ(m.state(), S::kPlan);
  EXPECT_TRUE(m.Handle(E::kLocalizationLost, 9.0, "lost again"));
  EXPECT_TRUE(m.Handle(E::kRelocalizationFailed, 39.0, "no pose on the map within 8 m"));
  EXPECT_EQ(m.state(), S::kFailed);
}

TEST(MissionStateTest, AMissionRunLogsEachChangeWithItsReason) {
  MissionStateMachine m;
  EXPECT_EQ(m.state(), S::kPlan);
  EXPECT_TRUE(m.Handle(E::kPathFound, 0.0, "path to park a"));
  EXPECT_FALSE(m.Handle(E::kWayClear, 1.0, "ignored in drive"));  // no row: no change, not logged
  EXPECT_TRUE(m.Handle(E::kAgentInWay, 2.0, "pedestrian"));
  EXPECT_TRUE(m.Handle(E::kCollisionImminent, 2.5, "emergency stop: pedestrian 3"));
  EXPECT_FALSE(m.Handle(E::kCollisionImminent, 2.6, "still"));
  EXPECT_TRUE(m.Handle(E::kCollisionCleared, 4.0, "clear"));
  EXPECT_TRUE(m.Handle(E::kPathFound, 4.1, "path again"));
  EXPECT_TRUE(m.Handle(E::kMissionComplete, 9.0, "reached park a"));
  EXPECT_TRUE(m.Final());
  EXPECT_FALSE(m.Handle(E::kCollisionImminent, 9.5, "after the end"));
  const std::vector<std::pair<std::string, std::string>> expected = {
      {"plan", "drive"},          {"drive", "wait"}, {"wait", "emergency_stop"},
      {"emergency_stop", "plan"}, {"plan", "drive"}, {"drive", "done"}};
  ASSERT_EQ(m.transitions().size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(m.transitions()[i].from, expected[i].first) << i;
    EXPECT_EQ(m.transitions()[i].to, expected[i].second) << i;
  }
  EXPECT_EQ(m.transitions()[2].reason, "emergency stop: pedestrian 3");
  EXPECT_DOUBLE_EQ(m.transitions()[2].t_s, 2.5);
}

}  // namespace
}  // namespace specht::decide
