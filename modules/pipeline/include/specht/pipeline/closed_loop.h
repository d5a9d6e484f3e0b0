// specht/pipeline/closed_loop.h: the mission state machine driving the simulated car.
//
// The states and their transition table are in decide/mission_state.h; here is when each
// event fires (every transition is logged with its time and reason):
//   path_found          hybrid A* + smoothing found a path to the current goal (the
//                       fine search, section hybrid_astar_fine, when the default
//                       finds none on the static map; in
//                       wait: a path around the blocking agents, tried once they
//                       block longer than replan_after_s, with them as obstacles
//                       inflated by their margins; no such path: keep waiting)
//   no_path             no path to the goal (the planner's reason)
//   agent_in_way        the path check sees an agent in the swept footprint ahead
//                       (pedestrians with pedestrian_margin_m, others agent_margin_m)
//   way_clear           that check has been clear for clear_s
//   goal_reached / mission_complete / goal_missed / goal_missed_final
//                       the path is driven; the car is within the goal's tolerance
//                       (another goal follows, or none), or not (a correction from
//                       where it stands, up to max_corrections times, then failure)
//   collision_imminent  the emergency check, whatever the state
//   collision_cleared   the emergency check has been clear for clear_s
//   time_limit          time_limit_s passed
//   localization_lost   the pose check (slam/pose_check.h, section pose_check) finds
//                       lost_after_scans scans in a row that disagree with the prior
//                       map at the believed pose: the car stops
//   relocalized         while lost, a scan is found on the prior map near the believed
//                       pose; the believed pose moves there and the machine replans
//   relocalization_failed  still lost after relocalize_timeout_s
//   sensor_blind        perception's latest frame is older than blind_stop_s (the car
//                       stops; from blind_slow_s it drives at most blind_slow_speed_mps)
//   sensor_restored     in blind: a frame younger than blind_slow_s
// What the machine reads about the world is a world-model snapshot (world/
// world_model.h): the static layer, the tracks and the latest perception frame's
// obstacles, written by perception (closed_loop.perception: the simulator's agents
// as they are; its noisy detections through the multi-object tracker; or the camera:
// our SGM and the CNN detector on the simulator's rendered stereo frames, box fusion
// at the believed pose, the tracker); it
// drives on the pose localisation believes (closed_loop.localization: the
// simulator's, or graph SLAM on the simulated LiDAR and odometry). The simulator's
// truth only scores the run: collisions, clearances, parking error, localisation
// error and perception's recall and precision.
// With perceived tracks the car sets off after track.confirm_window perception frames
// (0.5 s at the defaults): the time perception needs to confirm who stands around it.
// The path check does not use the planner's data: it tests the car's rectangle at
// the path poses within the stopping distance (+ 1.5 m) against the tracks' boxes,
// now and every 0.5 s up to prediction_s ahead at constant velocity, as a safety
// layer below the planner would. The emergency check uses neither path, tracks nor
// margins: the car's box stretched along its motion by the braking distance +
// emergency_buffer_m against the obstacles of perception's latest frame, and (with
// `lidar_stop`) stretched by the braking distance + lidar_stop_buffer_m against the
// raw returns of the latest LiDAR scan in the car's own frame, so that it needs
// neither the map nor the believed pose (Nav2's collision monitor works so). After
// a LiDAR stop, the returns near the car that neither the static layer nor a track
// explains become an obstacle layer both planners keep clear of until the goal
// changes (lidar_obstacle_range_m): what stopped the car, perception may not see.
//
// Planning layers: the path hybrid A* finds and the smoother smooths is the route;
// while driving, the local planner (plan/local_planner.h, section local_planner)
// replans every 1/rate_hz from the believed pose, speed and steering angle to a pose
// on the route a horizon ahead, with the tracks as moving obstacles (their boxes as
// discs, grown by the class margin), and the tracker follows its path with the
// route spliced on behind. Where it plans nothing by design (the last metres into a
// bay, a cusp) or finds nothing in time, the car keeps the path it follows, which
// runs on into the route: the last valid trajectory while the path and emergency
// checks find it free, then the route; the machine waits when both are blocked
// and asks hybrid A* for a path around after replan_after_s.
//
// Planning budget: a search on the car must end in time, but a replay whose paths
// depend on how fast the machine is would not be one (a sanitizer build or a busy
// CI runner would find other paths, or none). By default (planning_budget
// expansions) the searches here stop at their max_expansions only; the time each
// call took is still reported.
//
// The static layer is a prior map of the site: the map an earlier mapping drive
// left (`--map DIR`: LoopSlamConfig::site_map, localised on with localization map),
// else the scenario's true grid at kPlanningResolutionM; or (map_source lidar) the occupancy grid the car's simulated
// LiDAR builds as it drives, at the believed poses, returns on tracks removed, unknown cells free, rebuilt at
// map_update_hz — when it blocks the path ahead, map_changed sends the machine back to plan. The car is the scenario's
// ego; the simulator reports its box centre, the planner and tracker work on its rear axle (the point it turns about,
// ego.rear_overhang_m from the rear bumper).
#pragma once

#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "specht/decide/mission.h"
#include "specht/decide/mission_state.h"
#include "specht/detect/detector.h"
#include "specht/detect/fusion.h"
#include "specht/net/dds.h"
#include "specht/pipeline/map_artefact.h"
#include "specht/plan/hybrid_astar.h"
#include "specht/plan/local_planner.h"
#include "specht/plan/smoother.h"
#include "specht/plan/tracker.h"
#include "specht/sim/detections.h"
#include "specht/sim/scenario.h"
#include "specht/sim/sprites.h"
#include "specht/slam/graph_slam.h"
#include "specht/slam/pose_check.h"
#include "specht/stereo/sgm.h"
#include "specht/track/tracker.h"
#include "specht/world/world_model.h"

namespace specht::pipeline {

// The cell size the closed loop plans at: the true grid's, and a mapping drive's map.
inline constexpr double kPlanningResolutionM = 0.1;

// Section "closed_loop".
struct ClosedLoopOptions {
  double control_hz = 20;
  double pedestrian_margin_m = 1.0;
  double agent_margin_m = 0.5;
  double clear_s = 1.0;
  double prediction_s = 2.0;
  double replan_after_s = 8.0;
  double time_limit_s = 300;
  double park_tolerance_m = 0.2;
  double park_tolerance_deg = 5.0;
  double waypoint_tolerance_m = 0.5;
  int max_corrections = 3;
  double emergency_buffer_m = 0.3;
  bool lidar_stop = true;
  double lidar_stop_buffer_m = 0.1;
  double lidar_obstacle_range_m = 8.0;
  double pedestrian_slow_radius_m = 4.0;
  double pedestrian_slow_speed_mps = 1.0;
  double look_ahead_m = 15.0;
  double follow_gap_m = 2.0;
  double follow_gain = 0.5;
  std::string map_source = "truth";
  double map_update_hz = 2.0;
  double map_margin_m = 0.2;
  std::string planning_budget = "expansions";
  std::string localization = "truth";
  std::string perception = "truth";
  double perception_match_m = 1.0;
  double survey_spacing_m = 4.0;
  bool good_odometry = true;
  double kidnap_at_s = -1;
  double kidnap_m = 2.0;
  double kidnap_deg = 20.0;
  std::string video = "first";
  std::string mcap = "first";
  double relocalize_timeout_s = 30.0;
  double blind_slow_s = 0.2;
  double blind_stop_s = 0.4;
  double blind_slow_speed_mps = 1.0;
  double blind_at_s = -1;
  double blind_for_s = 5.0;

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Param("control_hz", control_hz, "planning/control loop rate", Range::Of(1.0, 100.0));
    v.Param("pedestrian_margin_m", pedestrian_margin_m, "never drive closer than this to a pedestrian",
            Range::Of(0.0, 10.0));
    v.Param("agent_margin_m", agent_margin_m, "clearance kept from cyclists and cars", Range::Of(0.0, 10.0));
    v.Param("prediction_s", prediction_s,
            "agents are checked where they will be up to this far ahead (constant velocity)", Range::Of(0.0, 10.0));
    v.Param("clear_s", clear_s, "how long the way must be clear before driving on", Range::Of(0.0, 60.0));
    v.Param("replan_after_s", replan_after_s, "replan around agents blocking longer than this", Range::Of(0.5, 600.0));
    v.Param("time_limit_s", time_limit_s, "the mission fails after this long", Range::Of(1.0, 36000.0));
    v.Param("park_tolerance_m", park_tolerance_m, "parked: position within this of the bay pose", Range::Of(0.01, 5.0));
    v.Param("park_tolerance_deg", park_tolerance_deg, "parked: heading within this", Range::Of(0.1, 90.0));
    v.Param("waypoint_tolerance_m", waypoint_tolerance_m, "a waypoint counts as reached within this",
            Range::Of(0.01, 10.0));
    v.Param("max_corrections", max_corrections, "replans from where the car stopped when it missed a goal",
            Range::Of(0, 100));
    v.Param("emergency_buffer_m", emergency_buffer_m,
            "emergency stop when an agent is within the braking distance plus this", Range::Of(0.0, 10.0));
    v.Param("lidar_stop", lidar_stop,
            "emergency stop also when a raw return of the latest LiDAR scan lies in the car's box stretched by "
            "the braking distance plus lidar_stop_buffer_m (car frame: no map, no pose)");
    v.Param("lidar_stop_buffer_m", lidar_stop_buffer_m, "…the stretch beyond the braking distance",
            Range::Of(0.0, 5.0));
    v.Param("lidar_obstacle_range_m", lidar_obstacle_range_m,
            "after a LiDAR stop, returns this close that neither the static layer nor a track explains become "
            "obstacles the planners keep clear of until the goal changes (0: none)",
            Range::Of(0.0, 30.0));
    v.Param("pedestrian_slow_radius_m", pedestrian_slow_radius_m,
            "slow down when a pedestrian is (or walks within prediction_s) this close to the path ahead "
            "(about the margin + the braking distance from 3 m/s)",
            Range::Of(0.0, 50.0));
    v.Param("pedestrian_slow_speed_mps", pedestrian_slow_speed_mps, "the speed limit near pedestrians",
            Range::Of(0.1, 20.0));
    v.Param("look_ahead_m", look_ahead_m, "how far along the path the speed decisions look", Range::Of(1.0, 200.0));
    v.Param("follow_gap_m", follow_gap_m, "gap kept to a lead cyclist or car beyond what the path check needs",
            Range::Of(0.0, 50.0));
    v.Param("follow_gain", follow_gain, "speed change per metre of gap error when following (1/s)",
            Range::Of(0.0, 10.0));
    v.Choice("map_source", map_source, {"truth", "lidar"},
             "plan on the scenario's true static map, or on the map the car's LiDAR builds as it drives");
    v.Param("map_update_hz", map_update_hz,
            "map_source lidar: how often the planning map is rebuilt and the path "
            "ahead checked against it",
            Range::Of(0.1, 20.0));
    v.Param("map_margin_m", map_margin_m,
            "map_source lidar: clearance planned beyond the car's safety margin "
            "(the path is given up only when the map leaves less than the safety margin)",
            Range::Of(0.0, 2.0));
    v.Choice("planning_budget", planning_budget, {"expansions", "time"},
             "searches stop at max_expansions alone, so a run's outcome does not depend on the machine's speed, "
             "or also at time_budget_ms, as on the car");
    v.Choice("localization", localization, {"truth", "slam", "map"},
             "where the car believes it is: the simulator's pose, graph SLAM on its LiDAR and odometry (mapping "
             "from scratch), or its LiDAR and odometry matched against a prior map of the site");
    v.Param("survey_spacing_m", survey_spacing_m,
            "localization map: the prior map is surveyed with a 360° scan this far apart over the free space",
            Range::Of(0.5, 50.0));
    v.Param("good_odometry", good_odometry,
            "SLAM in the loop takes the simulated car's odometry as good (slam::GoodOdometry, the values of "
            "params/good-odometry.yaml over scan_matching); off: scan_matching as given");
    v.Choice("perception", perception, {"truth", "detections", "camera"},
             "the road users it plans around: the simulator's agents; noisy detections (section "
             "synthetic_detections) through the tracker (section track) into the world model; or the camera: SGM "
             "(section stereo) and the CNN (section detect) on rendered stereo frames, box fusion, the tracker");
    v.Param("perception_match_m", perception_match_m,
            "in-loop scoring: a track within this of an agent counts as seeing it", Range::Of(0.1, 10.0));
    v.Choice("video", video, {"first", "all", "off"},
             "which drives of a run get a video (run-<seed>.mp4: the truth beside the world model the car drives "
             "on): the first seed's, every seed's, or none");
    v.Choice("mcap", mcap, {"first", "all", "off"},
             "which drives of a run are recorded as MCAP (run-<seed>.mcap, ROS 2 schemas, for Foxglove): the "
             "first seed's, every seed's, or none");
    v.Param("kidnap_at_s", kidnap_at_s, "a fault: from this time on the believed pose is off (< 0: never)",
            Range::Of(-1.0, 36000.0));
    v.Param("kidnap_m", kidnap_m, "…by this much ahead of the car", Range::Of(-50.0, 50.0));
    v.Param("kidnap_deg", kidnap_deg, "…and this much in heading", Range::Of(-180.0, 180.0));
    v.Param("relocalize_timeout_s", relocalize_timeout_s,
            "the mission fails when the pose, once lost (section pose_check), is not found on the map within this",
            Range::Of(0.1, 3600.0));
    v.Param("blind_slow_s", blind_slow_s,
            "perception's latest frame older than this: drive at most blind_slow_speed_mps", Range::Of(0.05, 60.0));
    v.Param("blind_stop_s", blind_stop_s, "…older than this: the sensor is blind, the car stops until frames come",
            Range::Of(0.05, 60.0));
    v.Param("blind_slow_speed_mps", blind_slow_speed_mps, "the speed limit while perception's frames are late",
            Range::Of(0.1, 20.0));
    v.Param("blind_at_s", blind_at_s, "a fault: perception delivers no frame from this time on (< 0: never)",
            Range::Of(-1.0, 36000.0));
    v.Param("blind_for_s", blind_for_s, "…for this long", Range::Of(0.0, 36000.0));
  }
  // "truth" (both oracles), "full" (SLAM and perceived tracks) or "mixed".
  std::string Stack() const;
  std::vector<std::string> Relations() const;
};

struct ClosedLoopResult {
  bool success = false;
  std::string failure;
  bool interrupted = false;                   // a signal stopped the drive (core/interrupt.h)
  int collisions = 0;                         // contacts (static or agent) begun while moving
  std::vector<std::string> collision_events;  // e.g. "12.30 s: pedestrian 7"
  double min_clearance_m = 1e9;               // footprint to static obstacles
  double min_pedestrian_m = 1e9;              // footprint to pedestrian boxes while moving
  std::string closest_pedestrian;             // when and who, e.g. "41.20 s: pedestrian 3"
  double time_s = 0;
  double park_error_m = -1, park_error_deg = -1;                    // of the last parking goal, by the truth
  double believed_park_error_m = -1, believed_park_error_deg = -1;  // …as the car believed it
  std::vector<double> plan_ms;
  std::map<std::string, double> limited_s;  // time driven below the tracker's speed, by decision (slow, follow)
  int map_replans = 0;                      // paths given up because the map changed under them
  // The local planner: calls (found, skipped where the route is followed by design,
  // failed), their latency and iterations, and the driving time on its paths.
  struct LocalPlanning {
    int calls = 0, found = 0, skipped = 0, failed = 0;
    std::vector<double> ms;
    long max_iterations = 0;
    int over_budget = 0;                  // calls longer than local_planner.time_budget_ms
    double driving_s = 0;                 // the car moving under a path
    double on_local_s = 0;                // …on a local planner's path
    double on_manoeuvre_s = 0;            // …on the route where no local plan is wanted (bay, cusps)
    std::map<std::string, int> failures;  // by reason
  } local;
  // Wall clock: the whole run and each stage (simulate, localize, perceive,
  // decide_and_plan), for the real-time factor; varies with the machine.
  double wall_s = 0;
  std::map<std::string, double> stage_ms;
  std::vector<decide::Transition> transitions;
  std::vector<plan::Pose> trajectory;  // at the control rate
  std::vector<plan::Path> paths;       // every plan made
  std::string stack;                   // ClosedLoopOptions::Stack()
  std::string static_layer;            // what the static layer started from: "site map", "true grid", "lidar"
  std::string video;                   // the run video written (file name), or ""
  std::string mcap;                    // the run's MCAP written (file name), or ""
  nlohmann::json localization;         // mode and trajectory error against the truth
  nlohmann::json perception;           // mode, frames, recall and precision per class
  // --nodes: the stack node's folder, the DDS domain, the wall-clock milliseconds per
  // control step until the stack acknowledged the step's inputs and until its decision
  // came (p50, p99, max), messages published by topic; null in process.
  nlohmann::json nodes;
  // localization slam: the map this drive drew, in the scenario's frame (a mapping
  // drive: what `--map` reads back).
  std::shared_ptr<const MapArtefact> drawn_map;
  nlohmann::json ToJson() const;
};

// The SLAM sections localisation in the loop runs with.
struct LoopSlamConfig {
  slam::SlamOptions slam;
  slam::ScanMatchingOptions matching;
  slam::LoopClosureOptions loops;
  slam::PoseGraphOptions graph;
  slam::GridOptions grid;         // the map a mapping drive leaves (its resolution: kPlanningResolutionM)
  double survey_spacing_m = 4.0;  // closed_loop.survey_spacing_m
  // localization map: the site's map from an earlier mapping drive (`specht run --map
  // DIR`, in the scenario's frame); none: a survey of the scenario's static world.
  std::shared_ptr<const MapArtefact> site_map;
};

// Perception camera: our SGM and the CNN detector on the simulator's stereo frames.
struct LoopCameraConfig {
  stereo::SgmOptions sgm;
  detect::DetectorOptions detector;
  detect::FusionOptions fusion;
  int downsample = 1;                           // perception.stereo_downsample
  std::string data_dir;                         // holds the detector's models
  const sim::SpriteLibrary* sprites = nullptr;  // agents drawn as photographs (none: boxes)
};

struct ClosedLoopConfig {
  plan::CarOptions car;  // limits; dimensions come from the scenario
  plan::HybridAStarOptions search;
  plan::HybridAStarOptions fine_search = plan::FineSearchDefaults();  // when `search` finds no path
  plan::SmootherOptions smoother;
  plan::TrackerOptions tracker;
  plan::KinodynamicOptions kinodynamic;  // the local planner's model (its budget: `local`)
  plan::LocalPlannerOptions local;
  ClosedLoopOptions loop;
  // What localisation and perception in the loop use (loop.localization, loop.perception).
  LoopSlamConfig slam;
  slam::PoseCheckOptions pose_check;  // where the believed pose can be wrong and the static layer is a prior map
  sim::SyntheticDetectionOptions detection;
  LoopCameraConfig camera;
  track::TrackerOptions tracking;
  world::WorldModelOptions world;
  // The run video (.mp4): the truth beside the world model the car drives on, from
  // above, 5 frames a simulated second played at 2×; "" for none.
  std::string video;
  // The run as MCAP (ROS 2 schemas, for Foxglove): the simulated LiDAR and odometry,
  // TF at the believed pose, the static layer, the path followed, the tracks, the
  // believed trajectory; "" for none.
  std::string mcap;
  // `specht run --nodes`: the stack runs as `specht node stack` (nodes.h) in a process
  // of its own and hears the car over DDS; none: in this process.
  struct StackNode {
    std::vector<std::string> command;  // the node's command line, but for --seed and -o
    // `specht node perception`'s command line but for -o, when the tracker runs in a
    // node of its own (--perception-node); empty: the stack node tracks.
    std::vector<std::string> perception_command;
    std::string out_dir;  // its output folder for seed N: <out_dir>/stack-N
    net::Options dds;
    double timeout_s = 60;  // the longest wait for the node to start or answer
  };
  std::optional<StackNode> stack_node;
};

// One control step as it happened: the state, the true pose and the believed one
// (rear axle), the number of tracks the machine saw.
struct LoopStep {
  double t_s = 0;
  std::string state;
  plan::Pose pose, believed;
  int tracks = 0;
  bool on_local_path = false;  // following a path of the local planner (else the route)
};

// Runs the mission; `on_step` (optional) after every control step.
ClosedLoopResult RunClosedLoop(const sim::Scenario& scenario, uint64_t seed, const std::vector<decide::Goal>& mission,
                               const ClosedLoopConfig& config,
                               const std::function<void(const LoopStep&)>& on_step = nullptr);

// The car the closed loop drives: the scenario's ego dimensions, rear overhang and
// limits over `base` (steering rate, reverse speed, margins).
plan::CarOptions ScenarioCar(const sim::Scenario& scenario, plan::CarOptions base);
// The ego's rear axle (the planner's pose) from its box centre (the simulator's).
plan::Pose EgoRearAxle(const sim::Scenario& scenario, const sim::Pose2& centre);
// What a mission file may name in `scenario`: its bays.
decide::MissionSite MissionSiteOf(const sim::Scenario& scenario);

}  // namespace specht::pipeline
