#include "specht/pipeline/closed_loop.h"

#include <mrpt/obs/CObservation2DRangeScan.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "internal/loop_geometry.h"
#include "internal/loop_localization.h"
#include "internal/loop_perception.h"
#include "internal/loop_video.h"
#include "internal/ros_recorder.h"
#include "specht/core/error.h"
#include "specht/core/interrupt.h"
#include "specht/sim/simulator.h"
#include "specht/sim/world.h"

namespace specht::pipeline {

using decide::Goal;
using decide::MissionEvent;
using decide::MissionState;
using decide::MissionStateMachine;
using decide::Transition;
using internal::Box;
using internal::Perceived;
using internal::SeenObject;

namespace {

Box AgentBox(const sim::AgentTruth& a) { return {a.pose.x, a.pose.y, a.pose.yaw_rad, a.length_m / 2, a.width_m / 2}; }

// The static map as the car's LiDAR sees it (map_source lidar): an MRPT occupancy
// grid over the scenario's extent, every scan inserted at the pose the car believes
// it had then, with the returns on perceived tracks removed. Unknown cells count as
// free for planning (a car explores optimistically and replans when a wall appears).
class LidarMap {
 public:
  explicit LidarMap(const plan::DistanceMap& extent)
      : grid_(static_cast<float>(extent.origin_x()),
              static_cast<float>(extent.origin_x() + extent.cols() * extent.resolution()),
              static_cast<float>(extent.origin_y()),
              static_cast<float>(extent.origin_y() + extent.rows() * extent.resolution()),
              static_cast<float>(extent.resolution())) {
    grid_.insertionOptions.maxDistanceInsertion = 25.0f;
    grid_.insertionOptions.considerInvalidRangesAsFreeSpace = false;
    grid_.insertionOptions.wideningBeamsWithDistance = false;
  }

  // A scan (its returns on road users already removed) at the pose believed for it.
  void Insert(const mrpt::obs::CObservation2DRangeScan& scan, const sim::Pose2& ego) {
    grid_.insertObservation(scan, internal::Pose3(ego));
    changed_ = true;
  }

  // Whether scans came in since the last call.
  bool TakeChanged() { return std::exchange(changed_, false); }
  const mrpt::maps::COccupancyGridMap2D& grid() const { return grid_; }

 private:
  mrpt::maps::COccupancyGridMap2D grid_;
  bool changed_ = true;  // the first map: all unknown
};

// The planning map of the world model's static layer. A map the car's LiDAR drew
// (map_source lidar as it drives, or a mapping drive's site map) counts its unknown
// cells as free: the LiDAR, mounted on the car, leaves ground around it unseen. A
// map still being drawn also widens its hits by a cell: a return marks the cell its
// point falls in, the true surface may lie in the neighbour, and at grazing angles
// neighbouring hits leave a cell between them (a finished map has seen its walls
// from many poses; widened, it closes the course's tight parallel bay).
std::shared_ptr<plan::DistanceMap> PlanningMap(const mrpt::maps::COccupancyGridMap2D& grid, bool lidar_drawn,
                                               bool being_drawn) {
  if (!lidar_drawn) return std::make_shared<plan::DistanceMap>(plan::DistanceMap::FromGrid(grid));
  const plan::DistanceMap seen = plan::DistanceMap::FromGrid(grid, false);
  if (!being_drawn) return std::make_shared<plan::DistanceMap>(seen);
  cv::Mat obstacles;
  cv::dilate(seen.obstacles(), obstacles, cv::Mat::ones(3, 3, CV_8U));
  return std::make_shared<plan::DistanceMap>(obstacles, seen.origin_x(), seen.origin_y(), seen.resolution());
}

// The search options with the wall clock taken out unless planning_budget is time.
plan::HybridAStarOptions Budgeted(const plan::HybridAStarOptions& o, const ClosedLoopOptions& loop) {
  return loop.planning_budget == "expansions" ? plan::WithoutTimeBudget(o) : o;
}

class Machine {
 public:
  Machine(const mrpt::maps::COccupancyGridMap2D& true_grid, const ClosedLoopConfig& c, const std::vector<Goal>& mission,
          uint64_t seed, ClosedLoopResult& r)
      : c_(c), mission_(mission), r_(r), seed_(static_cast<unsigned>(seed)) {
    truth_map_ = std::make_shared<plan::DistanceMap>(plan::DistanceMap::FromGrid(true_grid));
    // Paths on a map still being drawn (map_source lidar) keep map_margin_m more
    // clearance than the check that gives them up needs: a wall's outline firming up
    // by a cell as the car comes closer must not send it back to plan at every update.
    plan_car_ = c.car;
    if (c.loop.map_source == "lidar") plan_car_.safety_margin_m += c.loop.map_margin_m;
    search_options_ = Budgeted(c.search, c.loop), fine_options_ = Budgeted(c.fine_search, c.loop);
  }

  MissionState state() const { return machine_.state(); }
  // The path the car follows, from where it is on (rear axle, map frame); empty when none.
  std::vector<plan::Pose> PathAhead() const {
    std::vector<plan::Pose> ahead;
    if (!tracker_ || Final()) return ahead;
    const auto& points = tracker_->path().points;
    for (size_t i = tracker_->progress_index(); i < points.size(); ++i) ahead.push_back(points[i].pose);
    return ahead;
  }
  bool Final() const { return machine_.Final(); }
  const std::vector<Transition>& transitions() const { return machine_.transitions(); }
  // The true static map (what collisions and clearance are scored against).
  const plan::DistanceMap& truth_map() const { return *truth_map_; }

  // The planning map follows the world model's static layer: on a new one the
  // search starts over, and a path ahead it blocks is given up (map_changed → plan).
  void SyncMap(const world::Snapshot& snapshot, double t) {
    if (!snapshot.static_map || snapshot.static_map == planned_on_) return;
    planned_on_ = snapshot.static_map;
    const bool drawing = c_.loop.map_source == "lidar";
    static_map_ = PlanningMap(*snapshot.static_map, drawing || c_.slam.site_map, drawing);
    search_ = std::make_unique<plan::SearchWithFallback>(search_options_, fine_options_, plan_car_, static_map_);
    if (c_.local.enabled)
      local_ = std::make_unique<plan::LocalPlanner>(c_.local, c_.kinodynamic, plan_car_, static_map_);
    const MissionState state = machine_.state();
    if (!tracker_ || (state != MissionState::kDrive && state != MissionState::kWait)) return;
    const auto& points = tracker_->path().points;
    const plan::DiscCover discs = c_.car.Discs();
    for (size_t i = tracker_->progress_index(); i < points.size(); ++i)
      if (!static_map_->Free(discs, points[i].pose)) {
        char reason[96];
        std::snprintf(reason, sizeof(reason), "the map shows an obstacle on the path at (%.1f, %.1f)", points[i].pose.x,
                      points[i].pose.y);
        Handle(MissionEvent::kMapChanged, t, reason);
        ++r_.map_replans;
        return;
      }
  }

  // `returns`: the latest LiDAR scan's returns in the car's rear-axle frame;
  // `perception_age_s`: how old perception's latest frame (the track layer) is.
  plan::Command Step(double t, const plan::Pose& pose, double speed, double steer, const Perceived& seen,
                     const std::vector<cv::Point2d>& returns, double perception_age_s) {
    if (machine_.Final()) return {};
    if (machine_.state() == MissionState::kLocalizationLost) {  // stopped until relocalised (or given up)
      if (lost_since_ < 0) lost_since_ = t;
      if (t - lost_since_ > c_.loop.relocalize_timeout_s) {
        r_.failure = "localisation lost and not found on the map within " +
                     std::to_string(static_cast<int>(c_.loop.relocalize_timeout_s)) + " s";
        Handle(MissionEvent::kRelocalizationFailed, t, r_.failure);
      }
      return {};
    }
    lost_since_ = -1;
    perception_late_ = perception_age_s > c_.loop.blind_slow_s;
    if (perception_age_s > c_.loop.blind_stop_s) {
      char reason[96];
      std::snprintf(reason, sizeof(reason), "no perception frame for %.2f s", perception_age_s);
      Handle(MissionEvent::kSensorBlind, t, reason);
    } else if (!perception_late_ && machine_.state() == MissionState::kBlind) {
      Handle(MissionEvent::kSensorRestored, t, "perception frames again");
    }
    // The emergency check first: it overrides whatever the machine is doing.
    std::string what = ObstacleAhead(pose, speed, seen.obstacles);
    const bool by_lidar = what.empty() && !(what = ReturnAhead(speed, returns)).empty();
    if (!what.empty()) {
      if (by_lidar) RememberUnexplained(pose, returns, seen.tracks);
      Handle(MissionEvent::kCollisionImminent, t, what);
      estop_clear_since_ = -1;
      return {};
    }
    switch (machine_.state()) {
      case MissionState::kPlan:
        return Plan(t, pose, seen.tracks, false);
      case MissionState::kDrive:
        if (tracker_->finished()) return GoalReached(t, pose);
        if (const std::string who = Blocking(pose, speed, seen.tracks); !who.empty()) {
          Handle(MissionEvent::kAgentInWay, t, who + " in the way");
          blocked_since_ = t, clear_since_ = -1;
          return {};
        }
        if (local_ && t - local_at_s_ >= 1.0 / c_.local.rate_hz - 1e-9) LocalReplan(t, pose, speed, steer, seen.tracks);
        CountDriving(speed);
        return Limited(tracker_->Update(pose, speed, steer), pose, speed, seen.tracks);
      case MissionState::kWait:
        if (Blocking(pose, speed, seen.tracks).empty()) {
          if (clear_since_ < 0) clear_since_ = t;
          if (t - clear_since_ >= c_.loop.clear_s) Handle(MissionEvent::kWayClear, t, "the way is clear");
        } else {
          clear_since_ = -1;
          if (t - blocked_since_ > c_.loop.replan_after_s) return Plan(t, pose, seen.tracks, true);
        }
        return {};
      case MissionState::kEmergencyStop:
        if (estop_clear_since_ < 0) estop_clear_since_ = t;
        if (t - estop_clear_since_ >= c_.loop.clear_s)
          Handle(MissionEvent::kCollisionCleared, t, "nothing within the stopping distance");
        return {};
      default:
        return {};  // done, failed
    }
  }

  void Handle(MissionEvent event, double t, const std::string& reason) { machine_.Handle(event, t, reason); }
  // Whether the car follows a path of the local planner now.
  bool OnLocalPath() const {
    return tracker_ && machine_.state() == MissionState::kDrive && tracker_->progress_index() < local_points_;
  }

 private:
  // The local planner's call: on a path, the tracker follows it (the route spliced on
  // behind); otherwise the path being followed stays (see the header).
  void LocalReplan(double t, const plan::Pose& pose, double speed, double steer,
                   const std::vector<SeenObject>& tracks) {
    local_at_s_ = t;
    std::vector<plan::MovingObstacle> obstacles;
    for (const auto& a : tracks) {
      const auto discs =
          plan::BoxDiscs(a.box.x, a.box.y, a.box.theta, a.box.hl, a.box.hw, a.vx_mps, a.vy_mps, Margin(a));
      obstacles.insert(obstacles.end(), discs.begin(), discs.end());
    }
    for (const auto& p : unexplained_) obstacles.push_back({p.x, p.y, 0, 0, c_.loop.pedestrian_margin_m});
    auto& stats = r_.local;
    ++stats.calls;
    const plan::LocalPlan p =
        local_->Plan(pose, {speed, steer}, route_, route_index_, obstacles, seed_ * 7919u + stats.calls);
    route_index_ = p.route_index;
    if (p.skipped) {
      ++stats.skipped;
      manoeuvre_ = true;
      return;
    }
    manoeuvre_ = false;
    stats.ms.push_back(p.milliseconds);
    stats.max_iterations = std::max(stats.max_iterations, p.iterations);
    if (p.milliseconds > c_.local.time_budget_ms) ++stats.over_budget;
    if (!p.found) {
      ++stats.failed;
      ++stats.failures[p.failure.substr(0, p.failure.find(" ("))];
      return;
    }
    ++stats.found;
    local_points_ = p.local_points;
    tracker_.emplace(tracking_, c_.car, p.path);
  }

  void CountDriving(double speed) {
    if (std::abs(speed) < c_.tracker.stop_speed_mps) return;
    const double dt = 1.0 / c_.loop.control_hz;
    r_.local.driving_s += dt;
    if (OnLocalPath())
      r_.local.on_local_s += dt;
    else if (manoeuvre_)
      r_.local.on_manoeuvre_s += dt;
  }

  plan::Command Plan(double t, const plan::Pose& pose, const std::vector<SeenObject>& tracks, bool around_agents) {
    const Goal& goal = mission_[goal_];
    std::shared_ptr<plan::DistanceMap> map = static_map_;
    // Around agents or the LiDAR obstacle layer: the default search on a map with
    // them, the agents inflated by their margins, the returns by pedestrian_margin_m.
    std::unique_ptr<plan::HybridAStar> local;
    if (around_agents || !unexplained_.empty()) {
      cv::Mat obstacles = static_map_->obstacles().clone();
      const auto cell = [&](const cv::Point2d& p) {
        return cv::Point{static_cast<int>((p.x - map->origin_x()) / map->resolution()),
                         static_cast<int>((p.y - map->origin_y()) / map->resolution())};
      };
      if (around_agents)
        for (const auto& a : tracks) {
          Box b = a.box;
          const double m = Margin(a);
          b.hl += m, b.hw += m;
          std::vector<cv::Point> poly;
          for (const auto& p : internal::Corners(b)) poly.push_back(cell(p));
          cv::fillConvexPoly(obstacles, poly, cv::Scalar(1));
        }
      // A return's disc stops 0.2 m short of the car as it stands: the search needs
      // its start clear (a return at the bumper is left to the emergency stop).
      const Box car = internal::CarBox(c_.car, pose);
      for (const auto& p : unexplained_) {
        const double radius = std::min(c_.loop.pedestrian_margin_m, internal::PointToBox(p, car) - 0.2);
        if (radius >= 0)
          cv::circle(obstacles, cell(p), static_cast<int>(std::ceil(radius / map->resolution())), cv::Scalar(1),
                     cv::FILLED);
      }
      map = std::make_shared<plan::DistanceMap>(obstacles, static_map_->origin_x(), static_map_->origin_y(),
                                                static_map_->resolution());
      local = std::make_unique<plan::HybridAStar>(c_.search, plan_car_, map);
    }
    plan::PlanResult found;
    try {
      found = local ? local->Plan(pose, goal.pose) : search_->Plan(pose, goal.pose);
    } catch (const InputError& e) {
      found.failure = e.what();
    }
    r_.plan_ms.push_back(found.milliseconds + found.heuristic_milliseconds);
    if (!found.found) {
      if (around_agents) {  // keep waiting; the agents may move on
        blocked_since_ = t;
        return {};
      }
      if (!unexplained_.empty()) {  // no way past what the LiDAR saw: try the way it blocked again
        unexplained_.clear();
        return {};
      }
      r_.failure = "no path to " + goal.name + ": " + found.failure;
      Handle(MissionEvent::kNoPath, t, r_.failure);
      return {};
    }
    const plan::SmoothResult smooth = plan::SmoothPath(found.path, *map, plan_car_, c_.smoother);
    r_.plan_ms.back() += smooth.milliseconds;
    r_.paths.push_back(smooth.path);
    // The slow final approach is for parking precision; a waypoint is passed within
    // waypoint_tolerance_m and needs none.
    tracking_ = c_.tracker;
    if (!goal.park) tracking_.approach_distance_m = 0;
    tracker_.emplace(tracking_, c_.car, smooth.path);
    route_ = smooth.path, route_index_ = 0, local_points_ = 0, manoeuvre_ = false;
    local_at_s_ = -INFINITY;
    Handle(MissionEvent::kPathFound, t, "path to " + goal.name + (around_agents ? " around the agents" : ""));
    return {};
  }

  plan::Command GoalReached(double t, const plan::Pose& pose) {
    const Goal& goal = mission_[goal_];
    const double e_m = std::hypot(pose.x - goal.pose.x, pose.y - goal.pose.y);
    const double e_deg = std::abs(std::remainder(pose.theta - goal.pose.theta, 2 * M_PI)) * 180 / M_PI;
    if (goal.park) r_.believed_park_error_m = e_m, r_.believed_park_error_deg = e_deg;
    const bool ok = goal.park ? e_m <= c_.loop.park_tolerance_m && e_deg <= c_.loop.park_tolerance_deg
                              : e_m <= c_.loop.waypoint_tolerance_m;
    char note[128];
    std::snprintf(note, sizeof(note), "%s: %.3f m, %.1f° off", goal.name.c_str(), e_m, e_deg);
    if (!ok) {
      if (corrections_ < c_.loop.max_corrections) {  // a short manoeuvre from where the car stands
        ++corrections_;
        Handle(MissionEvent::kGoalMissed, t, std::string("correcting: ") + note);
        return {};
      }
      r_.failure = std::string("missed ") + note;
      Handle(MissionEvent::kGoalMissedFinal, t, r_.failure);
      return {};
    }
    corrections_ = 0;
    unexplained_.clear();  // what stopped the car on the way to the last goal
    if (++goal_ < mission_.size()) {
      Handle(MissionEvent::kGoalReached, t, std::string("reached ") + note);
      return {};
    }
    r_.success = true;
    Handle(MissionEvent::kMissionComplete, t, std::string("reached ") + note);
    return {};
  }

  // Class-dependent speed below the tracker's: while perception's frames are late,
  // at most blind_slow_speed_mps; near a pedestrian (now or where it
  // walks within prediction_s, closer than pedestrian_slow_radius_m to the path
  // ahead) at most pedestrian_slow_speed_mps — they turn without warning, and a
  // slow car stops within the margin; behind a cyclist or car going our way
  // (heading within 45° of ours) follow it: v = v_lead + follow_gain · (gap −
  // wanted), wanted = stopping distance + 1.5 m + the car's front + the lead's half
  // length + its margin + follow_gap_m, so the path check (which stops the car at
  // a gap a little short of that) rarely has to.
  plan::Command Limited(plan::Command cmd, const plan::Pose& pose, double speed,
                        const std::vector<SeenObject>& tracks) {
    const auto& points = tracker_->path().points;
    const int direction = cmd.speed_mps < 0 ? -1 : 1;
    std::vector<std::pair<plan::Pose, double>> ahead = {{pose, 0.0}};  // path poses and their distance along
    double along = 0;
    for (size_t i = tracker_->progress_index() + 1; i < points.size() && along < c_.loop.look_ahead_m; ++i) {
      along += std::hypot(points[i].pose.x - points[i - 1].pose.x, points[i].pose.y - points[i - 1].pose.y);
      if (points[i].direction != direction) break;
      if (along - ahead.back().second >= 0.5) ahead.push_back({points[i].pose, along});
    }
    const double heading = direction > 0 ? pose.theta : pose.theta + M_PI;
    const double front = c_.car.length_m - c_.car.rear_overhang_m;
    double limit = INFINITY;
    const char* kind = nullptr;  // the decision that sets the limit
    if (perception_late_) limit = c_.loop.blind_slow_speed_mps, kind = "blind";
    for (const auto& a : tracks) {
      const double x = a.box.x, y = a.box.y, vx = a.vx_mps, vy = a.vy_mps;
      if (a.cls == "pedestrian") {
        for (double dt = 0; dt <= c_.loop.prediction_s + 1e-9; dt += 0.5)
          for (const auto& [q, s] : ahead)
            if (std::hypot(x + vx * dt - q.x, y + vy * dt - q.y) < c_.loop.pedestrian_slow_radius_m &&
                c_.loop.pedestrian_slow_speed_mps < limit)
              limit = c_.loop.pedestrian_slow_speed_mps, kind = "slow";
        continue;
      }
      const double a_speed = std::hypot(vx, vy), cos_rel = std::cos(std::atan2(vy, vx) - heading);
      if (cos_rel < std::cos(M_PI / 4) || a_speed * cos_rel < 0.3) continue;
      const double reach = c_.car.width_m / 2 + a.box.hw + c_.loop.agent_margin_m;
      for (const auto& [q, s] : ahead) {
        if (std::hypot(x - q.x, y - q.y) > reach) continue;
        const double wanted = speed * speed / (2 * c_.car.max_accel_mps2) + 1.5 + front + a.box.hl +
                              c_.loop.agent_margin_m + c_.loop.follow_gap_m;
        const double v = std::max(0.0, a_speed * cos_rel + c_.loop.follow_gain * (s - wanted));
        if (v < limit) limit = v, kind = "follow";
        break;
      }
    }
    if (kind && std::abs(cmd.speed_mps) > limit) {
      cmd.speed_mps = direction * limit;
      r_.limited_s[kind] += 1.0 / c_.loop.control_hz;
    }
    return cmd;
  }

  // The emergency check, independent of the path, the planner and the margins:
  // the car's box stretched in its direction of travel by the braking distance
  // v²/(2 a) + emergency_buffer_m, against the obstacles of perception's latest
  // frame (not the tracks); then (ReturnAhead) stretched by v²/(2 a) +
  // lidar_stop_buffer_m against the LiDAR's raw returns in the car's frame. Each
  // returns what the car would hit ("" when nothing). A stopped car needs no check.
  std::string ObstacleAhead(const plan::Pose& pose, double speed, const std::vector<SeenObject>& obstacles) const {
    if (std::abs(speed) < c_.tracker.stop_speed_mps) return "";
    const Box box = Stretched(pose, speed, Braking(speed) + c_.loop.emergency_buffer_m);
    for (const auto& o : obstacles)
      if (internal::BoxToBox(box, o.box) <= 0) return "emergency stop: " + o.Name() + " within the stopping distance";
    return "";
  }

  std::string ReturnAhead(double speed, const std::vector<cv::Point2d>& returns) const {
    if (!c_.loop.lidar_stop || std::abs(speed) < c_.tracker.stop_speed_mps) return "";
    const Box own = Stretched({0, 0, 0}, speed, Braking(speed) + c_.loop.lidar_stop_buffer_m);
    for (const auto& p : returns)
      if (internal::PointToBox(p, own) <= 0) {
        char what[96];
        std::snprintf(what, sizeof(what), "emergency stop: a LiDAR return %.2f m %s within the stopping distance",
                      std::hypot(p.x, p.y), p.x >= 0 ? "ahead" : "behind");
        return what;
      }
    return "";
  }

  double Braking(double speed) const { return speed * speed / (2 * c_.car.max_accel_mps2); }

  // The LiDAR obstacle layer: after a LiDAR stop, the returns within
  // lidar_obstacle_range_m that neither the static layer (within 0.3 m of an
  // occupied cell) nor a track's box explains, in the map frame at the believed pose.
  // The planners keep clear of them by pedestrian_margin_m (nobody knows what they
  // are) until the goal changes: what stopped the car, perception may not see.
  void RememberUnexplained(const plan::Pose& pose, const std::vector<cv::Point2d>& returns,
                           const std::vector<SeenObject>& tracks) {
    const double c = std::cos(pose.theta), s = std::sin(pose.theta);
    for (const auto& p : returns) {
      if (std::hypot(p.x, p.y) > c_.loop.lidar_obstacle_range_m) continue;
      const cv::Point2d w{pose.x + c * p.x - s * p.y, pose.y + s * p.x + c * p.y};
      if (!static_map_->Contains(w.x, w.y) || static_map_->Distance(w.x, w.y) < 0.3) continue;
      const bool on_track = std::any_of(tracks.begin(), tracks.end(),
                                        [&](const SeenObject& a) { return internal::PointToBox(w, a.box) < 0.3; });
      const bool known = std::any_of(unexplained_.begin(), unexplained_.end(),
                                     [&](const cv::Point2d& q) { return std::hypot(q.x - w.x, q.y - w.y) < 0.1; });
      if (!on_track && !known) unexplained_.push_back(w);
    }
  }

  // The car's box at `pose` stretched by `reach` in its direction of travel.
  Box Stretched(const plan::Pose& pose, double speed, double reach) const {
    Box box = internal::CarBox(c_.car, pose);
    const double shift = (speed > 0 ? 1 : -1) * reach / 2;
    box.x += shift * std::cos(pose.theta), box.y += shift * std::sin(pose.theta), box.hl += reach / 2;
    return box;
  }

  // The independent check: the car's box at the path poses within the stopping
  // distance (+ 1.5 m), and where it stands, against the tracks' boxes now and
  // predicted at constant velocity. Returns the first track in the way ("" when none).
  std::string Blocking(const plan::Pose& pose, double speed, const std::vector<SeenObject>& tracks) const {
    const auto& points = tracker_->path().points;
    const double reach = speed * speed / (2 * c_.car.max_accel_mps2) + 1.5;
    std::vector<Box> swept = {internal::CarBox(c_.car, pose)};
    double along = 0;
    for (size_t i = tracker_->progress_index() + 1; i < points.size() && along < reach; ++i) {
      along += std::hypot(points[i].pose.x - points[i - 1].pose.x, points[i].pose.y - points[i - 1].pose.y);
      swept.push_back(internal::CarBox(c_.car, points[i].pose));
    }
    for (const auto& a : tracks) {
      const double margin = Margin(a);
      // The track where it is and where it would be, going straight on, over the
      // prediction horizon: a cyclist about to cross counts before it arrives.
      for (double dt = 0; dt <= c_.loop.prediction_s + 1e-9; dt += 0.5) {
        Box b = a.box;
        b.x += a.vx_mps * dt, b.y += a.vy_mps * dt;
        if (std::hypot(b.x - pose.x, b.y - pose.y) > reach + c_.car.length_m + margin + 5) continue;
        for (const auto& box : swept)
          if (internal::BoxToBox(box, b) < margin) return a.Name();
      }
    }
    return "";
  }

  // The clearance kept from a road user: pedestrians pedestrian_margin_m, others agent_margin_m.
  double Margin(const SeenObject& a) const {
    return a.cls == "pedestrian" ? c_.loop.pedestrian_margin_m : c_.loop.agent_margin_m;
  }

  const ClosedLoopConfig& c_;
  const std::vector<Goal>& mission_;
  ClosedLoopResult& r_;
  std::shared_ptr<plan::DistanceMap> truth_map_, static_map_;          // scored against, planned on
  std::shared_ptr<const mrpt::maps::COccupancyGridMap2D> planned_on_;  // the static layer static_map_ is of
  plan::CarOptions plan_car_;  // the car the planner sees (the LiDAR map's extra margin)
  plan::HybridAStarOptions search_options_, fine_options_;
  std::unique_ptr<plan::SearchWithFallback> search_;
  std::optional<plan::PathTracker> tracker_;
  plan::TrackerOptions tracking_;  // the current goal's (no slow approach to a waypoint)
  // The local planner on static_map_, the route it follows (the smoothed global
  // path), the route's index the car has passed, how many points of the tracked path
  // are a local plan's, whether the last call left the car on the route by design.
  std::unique_ptr<plan::LocalPlanner> local_;
  plan::Path route_;
  size_t route_index_ = 0, local_points_ = 0;
  bool manoeuvre_ = false;
  double local_at_s_ = -INFINITY;
  unsigned seed_;
  std::vector<cv::Point2d> unexplained_;  // the LiDAR obstacle layer (map frame)
  MissionStateMachine machine_;
  size_t goal_ = 0;
  int corrections_ = 0;
  double blocked_since_ = 0, clear_since_ = -1, estop_clear_since_ = -1, lost_since_ = -1;
  bool perception_late_ = false;  // perception's latest frame older than blind_slow_s
};

}  // namespace

plan::Pose EgoRearAxle(const sim::Scenario& s, const sim::Pose2& centre) {
  const double back = s.ego.model.PivotAhead();
  return {centre.x - back * std::cos(centre.yaw_rad), centre.y - back * std::sin(centre.yaw_rad), centre.yaw_rad};
}

decide::MissionSite MissionSiteOf(const sim::Scenario& s) {
  decide::MissionSite site{"scenario " + s.name, {}};
  for (const auto& b : s.bays) site.bays.push_back({b.name, b.pose.x, b.pose.y, b.pose.yaw_rad, b.length_m, b.width_m});
  return site;
}

plan::CarOptions ScenarioCar(const sim::Scenario& s, plan::CarOptions car) {
  const sim::VehicleModel& v = s.ego.model;
  car.wheelbase_m = v.wheelbase_m, car.max_steer_deg = v.max_steer_rad * 180 / M_PI;
  car.length_m = v.length_m, car.width_m = v.width_m, car.rear_overhang_m = v.rear_overhang_m;
  car.max_speed_mps = std::min(car.max_speed_mps, v.max_speed_mps);
  car.max_accel_mps2 = v.max_accel_mps2;
  return car;
}

namespace {

// Scores one simulator step against the truth: contacts with the true static map or
// an agent while moving (counted once per contact), clearances.
class ContactScore {
 public:
  ContactScore(const sim::Scenario& s, const ClosedLoopConfig& c, const plan::DistanceMap& truth)
      : s_(s), c_(c), truth_(truth) {}

  void Step(const sim::Simulator& sim, ClosedLoopResult& r) {
    const auto& e = sim.ego();
    const Box car = internal::CarBox(c_.car, EgoRearAxle(s_, e.pose));
    const bool moving = std::abs(e.speed_mps) > 0.05;
    const double clearance = internal::OutlineClearance(truth_, car);
    r.min_clearance_m = std::min(r.min_clearance_m, clearance);
    std::string what = clearance <= 0 ? "static obstacle" : "";
    for (const auto& a : sim.agents()) {
      const double d = internal::BoxToBox(car, AgentBox(a));
      if (moving && a.cls == sim::AgentClass::kPedestrian && d < r.min_pedestrian_m) {
        r.min_pedestrian_m = d;
        char at[64];
        std::snprintf(at, sizeof(at), "%.2f s: pedestrian %d", sim.time_s(), a.id);
        r.closest_pedestrian = at;
      }
      if (moving && d <= 0) what = std::string(sim::Name(a.cls)) + " " + std::to_string(a.id);
    }
    const bool contact = !what.empty();
    if (contact && !touching_) {
      ++r.collisions;
      char buf[96];
      std::snprintf(buf, sizeof(buf), "%.2f s: %s", sim.time_s(), what.c_str());
      r.collision_events.push_back(buf);
    }
    touching_ = contact;
  }

 private:
  const sim::Scenario& s_;
  const ClosedLoopConfig& c_;
  const plan::DistanceMap& truth_;
  bool touching_ = false;
};

// The parking error against the truth: the machine judged its goals on the pose it
// believed, so a mission it completed on a wrong belief fails here.
void ScoreParking(const ClosedLoopConfig& c, const std::vector<Goal>& mission, const plan::Pose& truth,
                  ClosedLoopResult& r) {
  if (r.believed_park_error_m < 0 || !mission.back().park) return;
  const plan::Pose& goal = mission.back().pose;
  r.park_error_m = std::hypot(truth.x - goal.x, truth.y - goal.y);
  r.park_error_deg = std::abs(std::remainder(truth.theta - goal.theta, 2 * M_PI)) * 180 / M_PI;
  if (!r.success || (r.park_error_m <= c.loop.park_tolerance_m && r.park_error_deg <= c.loop.park_tolerance_deg))
    return;
  r.success = false;
  char note[160];
  std::snprintf(note, sizeof(note), "parked %.3f m, %.1f° off by the truth (%.3f m, %.1f° as believed)", r.park_error_m,
                r.park_error_deg, r.believed_park_error_m, r.believed_park_error_deg);
  r.failure = note;
}

// The believed pose against the prior map (slam/pose_check.h): every scan, its
// returns on tracks removed, scored where the car believes it took it; lost after
// lost_after_scans disagreeing scans in a row, then searched for on the map at every
// scan until found.
class LoopPoseCheck {
 public:
  LoopPoseCheck(std::shared_ptr<const mrpt::maps::COccupancyGridMap2D> prior_map, const slam::PoseCheckOptions& options)
      : prior_map_(std::move(prior_map)), check_(*prior_map_, options), monitor_(options) {}

  // `scan` (returns on tracks removed) taken at the believed box-centre pose `at`.
  void Observe(const mrpt::obs::CObservation2DRangeScan& scan, double t, internal::LoopLocalization& where,
               const sim::Simulator& sim, Machine& machine) {
    mrpt::maps::CSimplePointsMap points;
    internal::ForEachReturn(scan, {0, 0, 0},
                            [&](size_t, const cv::Point2d& p) { points.insertPointFast(p.x, p.y, 0); });
    const sim::Pose2 at = where.AtLatestScan(sim);
    const mrpt::poses::CPose2D believed(at.x, at.y, at.yaw_rad);
    if (machine.state() == MissionState::kLocalizationLost) {
      const auto found = check_.Relocalize(points, believed);
      if (!found) return;
      where.Relocalize(sim, {found->pose.x(), found->pose.y(), found->pose.phi()});
      monitor_.Reset();
      ++relocalized_;
      char reason[128];
      std::snprintf(reason, sizeof(reason), "relocalised %.2f m, %.1f° from the lost pose (score %.2f)",
                    std::hypot(found->pose.x() - at.x, found->pose.y() - at.y),
                    std::abs(std::remainder(found->pose.phi() - at.yaw_rad, 2 * M_PI)) * 180 / M_PI, found->score);
      machine.Handle(MissionEvent::kRelocalized, t, reason);
      return;
    }
    const std::optional<double> score = check_.Score(points, believed);
    if (!monitor_.Add(score) || machine.Final()) return;
    ++lost_;
    char reason[128];
    std::snprintf(reason, sizeof(reason), "%d scans in a row disagree with the map at the believed pose (score %.2f)",
                  check_.options().lost_after_scans, *score);
    machine.Handle(MissionEvent::kLocalizationLost, t, reason);
  }

  nlohmann::json ToJson() const {
    return {{"scans_scored", monitor_.scored()},
            {"scans_disagreeing", monitor_.disagreeing_total()},
            {"lowest_score", monitor_.lowest()},
            {"lost", lost_},
            {"relocalized", relocalized_}};
  }

 private:
  std::shared_ptr<const mrpt::maps::COccupancyGridMap2D> prior_map_;  // the check reads it
  slam::PoseCheck check_;
  slam::PoseMonitor monitor_;
  int lost_ = 0, relocalized_ = 0;
};

// The closed loop as MCAP (internal/ros_recorder.h): every observation, and at each
// control step the believed pose for /trajectory and, twice a second, the static
// layer when it changed, the path the car follows and the tracks' poses.
class LoopRecording {
 public:
  LoopRecording(const std::string& path, const slam::GridOptions& grid) : record_(Sinks(path), 0.0, grid) {}
  void Observation(Stamp t, const mrpt::obs::CObservation::Ptr& o) { record_.Observation(t, o); }
  void ScanPose(Stamp t, const sim::Pose2& believed) { record_.Pose(t, internal::Pose3(believed)); }
  void Step(Stamp t, const sim::Pose2& believed, const world::Snapshot& snapshot, const Perceived& seen,
            const std::vector<plan::Pose>& path) {
    believed_.push_back({t, internal::Pose3(believed)});
    if (t.Seconds() - last_s_ < 0.5) return;
    last_s_ = t.Seconds();
    if (snapshot.static_map && snapshot.static_map != map_) {
      record_.Map(*snapshot.static_map, t);
      map_ = snapshot.static_map;
    }
    std::vector<mrpt::poses::CPose3D> ahead, tracks;
    for (const auto& p : path) ahead.emplace_back(p.x, p.y, 0, p.theta, 0, 0);
    for (const auto& o : seen.tracks) tracks.emplace_back(o.box.x, o.box.y, 0, o.box.theta, 0, 0);
    record_.Path("/path", ahead, t);
    record_.Poses("/tracks", tracks, t);
  }
  void Finish(const mrpt::maps::COccupancyGridMap2D& grid, Stamp end) { record_.Finish(grid, believed_, end); }

 private:
  static std::vector<std::unique_ptr<internal::MessageSink>> Sinks(const std::string& path) {
    std::vector<std::unique_ptr<internal::MessageSink>> sinks;
    sinks.push_back(internal::McapSink(path));
    return sinks;
  }
  internal::RosRecorder record_;
  Trajectory believed_;  // at the control rate, for /trajectory
  double last_s_ = -INFINITY;
  std::shared_ptr<const mrpt::maps::COccupancyGridMap2D> map_;  // the static layer recorded last
};

}  // namespace

std::vector<std::string> ClosedLoopOptions::Relations() const {
  if (blind_stop_s <= blind_slow_s) return {"blind_stop_s must be above blind_slow_s"};
  return {};
}

std::string ClosedLoopOptions::Stack() const {
  if (localization == "truth" && perception == "truth") return "truth";
  if (localization != "truth" && perception != "truth") return "full";
  return "mixed";
}

ClosedLoopResult RunClosedLoop(const sim::Scenario& scenario, uint64_t seed, const std::vector<Goal>& mission,
                               const ClosedLoopConfig& config, const std::function<void(const LoopStep&)>& on_step) {
  if (mission.empty()) throw InputError("closed loop: the mission has no goals");
  const ClosedLoopOptions& loop = config.loop;
  ClosedLoopResult r;
  const bool camera = loop.perception == "camera";
  if (camera && !scenario.stereo)
    throw InputError("closed_loop.perception camera: scenario " + scenario.name + " has no stereo camera");
  const std::shared_ptr<const MapArtefact>& site_map = config.slam.site_map;
  if (site_map && loop.localization != "map")
    throw InputError("a map of the site is given, but closed_loop.localization is " + loop.localization +
                     " (it is read by localization map)");
  sim::Simulator sim(scenario, seed, camera ? config.camera.sprites : nullptr);
  world::WorldModel world(config.world);
  LoopSlamConfig slam_config = config.slam;
  slam_config.survey_spacing_m = loop.survey_spacing_m;
  // The simulated car's odometry is good to about 1 % of a step (sensors.odometry); the
  // scan_matching defaults are sized for logs whose odometry drifts tens of metres.
  if (loop.good_odometry) slam_config.matching = slam::GoodOdometry(slam_config.matching);
  internal::LoopLocalization where(loop.localization, scenario, slam_config,
                                   {loop.kidnap_at_s, loop.kidnap_m, loop.kidnap_deg});
  internal::LoopPerception perceive(loop.perception, loop.control_hz, config.detection, config.tracking,
                                    loop.perception_match_m, seed, world, {loop.blind_at_s, loop.blind_for_s},
                                    config.camera);
  const mrpt::maps::COccupancyGridMap2D true_grid = sim::World(scenario).TrueGrid(kPlanningResolutionM);
  Machine machine(true_grid, config, mission, seed, r);
  ContactScore contacts(scenario, config, machine.truth_map());
  const int substeps = std::max(1, static_cast<int>(std::lround(1.0 / (loop.control_hz * sim::Simulator::kStepS))));
  std::optional<LidarMap> lidar;
  if (loop.map_source == "lidar")
    lidar.emplace(machine.truth_map());  // nothing seen yet
  else                                   // a prior map of the site: a mapping drive's, or the scenario's true grid
    world.SetStaticMap(site_map ? site_map->grid : true_grid, sim.stamp());
  // The pose check needs a prior map, and a pose that can be wrong.
  std::optional<LoopPoseCheck> pose_check;
  if (config.pose_check.enabled && !lidar && (loop.localization != "truth" || loop.kidnap_at_s >= 0))
    pose_check.emplace(world.snapshot()->static_map, config.pose_check);
  perceive.Step(sim, where.Believed(sim));
  // Scans reach SLAM and the LiDAR map without their returns on tracked road users:
  // a car driving ahead along a street whose walls leave the scan matcher free along
  // it would carry the car's believed pose with it.
  std::vector<cv::Point2d> returns;  // the latest scan's, rear-axle frame (the emergency check's)
  const sim::Pose2 centre_from_axle{scenario.ego.model.PivotAhead(), 0, 0};
  // Wall-clock time per stage (the report's timing; never a pass/fail figure).
  using Clock = std::chrono::steady_clock;
  const auto since = [](Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  };
  const auto run_start = Clock::now();
  std::optional<LoopRecording> record;  // the run as MCAP (config.mcap)
  if (!config.mcap.empty()) record.emplace(config.mcap, config.slam.grid);
  const auto observe = [&](Stamp t, const mrpt::obs::CObservation::Ptr& obs) {
    if (record) record->Observation(t, obs);
    const auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs);
    if (!scan) return where.Observe(t, obs);
    returns.clear();
    if (loop.lidar_stop)
      internal::ForEachReturn(*scan, centre_from_axle, [&](size_t, const cv::Point2d& p) { returns.push_back(p); });
    if (!lidar && !where.UsesObservations() && !pose_check) return;  // nothing reads the scan
    const auto tracks = internal::PerceivedFrom(*world.snapshot()).tracks;
    const auto kept = internal::WithoutReturnsOn(*scan, where.Believed(sim), tracks);
    where.Observe(t, kept);
    if (record) record->ScanPose(t, where.AtLatestScan(sim));
    if (lidar) lidar->Insert(*kept, where.AtLatestScan(sim));
    if (pose_check) pose_check->Observe(*kept, sim.time_s(), where, sim, machine);
  };
  const auto on_observation = [&](Stamp t, const mrpt::obs::CObservation::Ptr& obs) {
    const auto t0 = Clock::now();
    observe(t, obs);
    r.stage_ms["localize"] += since(t0);
  };
  // Rendered stereo frames, only where perception reads them (rendering costs).
  sim::Simulator::StereoSink on_stereo;
  if (camera)
    on_stereo = [&](Stamp, const sim::StereoFrame& frame) {
      const auto t0 = Clock::now();
      perceive.Camera(sim, frame, where.Believed(sim));
      r.stage_ms["perceive"] += since(t0);
      r.stage_ms["camera_in_simulate"] += since(t0);
    };
  const double frame_rate_hz = camera ? scenario.stereo->rate_hz : config.detection.rate_hz;
  const double warmup_s = loop.perception == "truth" ? 0.0 : config.tracking.confirm_window / frame_rate_hz;
  std::optional<internal::LoopVideo> video;
  if (!config.video.empty()) video.emplace(config.video, true_grid, config.world, sim.stamp());
  double map_updated_s = -INFINITY;
  while (!machine.Final()) {
    const double t = sim.time_s();
    if (InterruptRequested()) {  // stop at this control step; what was driven is the result
      r.interrupted = true;
      r.failure = "interrupted by " + InterruptName() + " at " + std::to_string(t) + " s";
      break;
    }
    if (t > loop.time_limit_s) {
      r.failure = "time limit of " + std::to_string(loop.time_limit_s) + " s";
      machine.Handle(MissionEvent::kTimeLimit, t, r.failure);
      break;
    }
    if (lidar && t - map_updated_s >= 1.0 / loop.map_update_hz - 1e-9) {
      if (lidar->TakeChanged()) world.SetStaticMap(lidar->grid(), sim.stamp());
      map_updated_s = t;
    }
    const auto snapshot = world.snapshot();
    machine.SyncMap(*snapshot, t);
    where.Tick(sim);
    where.Score(sim);
    const auto& ego = sim.ego();
    const plan::Pose believed = EgoRearAxle(scenario, where.Believed(sim));
    const double perception_age_s = SecondsBetween(snapshot->tracks_stamp, sim.stamp());
    const Perceived seen = internal::PerceivedFrom(*snapshot, perception_age_s);
    auto t0 = Clock::now();
    // The car sets off once perception could have confirmed the road users around it.
    const plan::Command cmd =
        t < warmup_s ? plan::Command{}
                     : machine.Step(t, believed, ego.speed_mps, ego.steer_rad, seen, returns, perception_age_s);
    r.stage_ms["decide_and_plan"] += since(t0);
    sim.CommandEgo({cmd.speed_mps, cmd.steer_rad, config.car.max_steer_rate_deg_s * M_PI / 180});
    const plan::Pose pose = EgoRearAxle(scenario, ego.pose);
    r.trajectory.push_back(pose);
    const std::vector<plan::Pose> ahead = video || record ? machine.PathAhead() : std::vector<plan::Pose>{};
    if (video) {
      t0 = Clock::now();
      video->Step(sim, *snapshot, where.Believed(sim), ahead);
      r.stage_ms["video"] += since(t0);
    }
    if (record) {
      t0 = Clock::now();
      record->Step(sim.stamp(), where.Believed(sim), *snapshot, seen, ahead);
      r.stage_ms["mcap"] += since(t0);
    }
    if (on_step)
      on_step({t, decide::Name(machine.state()), pose, believed, static_cast<int>(seen.tracks.size()),
               machine.OnLocalPath()});
    for (int k = 0; k < substeps; ++k) {
      t0 = Clock::now();
      sim.Step(on_observation, on_stereo);  // localisation and camera perception run inside
      r.stage_ms["simulate"] += since(t0);
      t0 = Clock::now();
      perceive.Step(sim, where.Believed(sim));
      r.stage_ms["perceive"] += since(t0);
      contacts.Step(sim, r);
    }
  }
  r.time_s = sim.time_s();
  if (video) r.video = video->Close();
  if (record) {
    const auto last = world.snapshot();
    record->Finish(last->static_map ? *last->static_map : true_grid, sim.stamp());
    r.mcap = std::filesystem::path(config.mcap).filename().string();
  }
  // What ran inside the simulator's step belongs to its own stage; rendering is its own.
  r.stage_ms["simulate"] -= r.stage_ms["localize"] + r.stage_ms["camera_in_simulate"] + 1e3 * sim.render_seconds();
  r.stage_ms.erase("camera_in_simulate");
  if (camera) r.stage_ms["render"] = 1e3 * sim.render_seconds();
  r.wall_s = since(run_start) / 1e3;
  r.transitions = machine.transitions();
  ScoreParking(config, mission, EgoRearAxle(scenario, sim.ego().pose), r);
  r.stack = loop.Stack();
  r.static_layer = lidar ? "lidar" : site_map ? "site map" : "true grid";
  r.localization = where.ToJson();
  if (pose_check) r.localization["pose_check"] = pose_check->ToJson();
  r.perception = perceive.ToJson();
  slam::GridOptions drawn = config.slam.grid;
  drawn.resolution_m = kPlanningResolutionM;
  r.drawn_map = where.DrawnMap(scenario.name, drawn);
  return r;
}

namespace {

// p50, p90 and max of `values` (0 when there are none).
nlohmann::json Quantiles(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const auto q = [&](double p) {
    return values.empty() ? 0.0 : values[std::min(values.size() - 1, static_cast<size_t>(p * values.size()))];
  };
  return {{"count", values.size()}, {"p50", q(0.5)}, {"p90", q(0.9)}, {"max", values.empty() ? 0.0 : values.back()}};
}

// Wall-clock milliseconds per stage per simulated second.
nlohmann::json PerSecond(const std::map<std::string, double>& stage_ms, double sim_s) {
  nlohmann::json out = nlohmann::json::object();
  for (const auto& [stage, ms] : stage_ms) out[stage] = sim_s > 0 ? ms / sim_s : 0.0;
  return out;
}

nlohmann::json LocalToJson(const ClosedLoopResult::LocalPlanning& l) {
  const double outside = l.driving_s - l.on_manoeuvre_s;
  return {{"calls", l.calls},
          {"found", l.found},
          {"skipped", l.skipped},
          {"failed", l.failed},
          {"failures", l.failures},
          {"success_rate", l.calls - l.skipped > 0 ? static_cast<double>(l.found) / (l.calls - l.skipped) : 0.0},
          {"ms", Quantiles(l.ms)},
          {"max_iterations", l.max_iterations},
          {"over_budget", l.over_budget},
          {"driving_s", l.driving_s},
          {"on_local_path_s", l.on_local_s},
          {"on_manoeuvre_s", l.on_manoeuvre_s},
          {"share_outside_manoeuvres", outside > 0 ? l.on_local_s / outside : 0.0}};
}

}  // namespace

nlohmann::json ClosedLoopResult::ToJson() const {
  nlohmann::json states = nlohmann::json::array(), visited = nlohmann::json::array();
  for (const auto& tr : transitions) {
    states.push_back({{"t_s", tr.t_s}, {"from", tr.from}, {"to", tr.to}, {"reason", tr.reason}});
    if (std::find(visited.begin(), visited.end(), tr.to) == visited.end()) visited.push_back(tr.to);
  }
  return {{"success", success},
          {"failure", failure},
          {"stack", stack},
          {"static_layer", static_layer},
          {"video", video},
          {"mcap", mcap},
          {"localization", localization},
          {"perception", perception},
          {"interrupted", interrupted},
          {"collisions", collisions},
          {"collision_events", collision_events},
          {"min_clearance_m", min_clearance_m},
          {"min_pedestrian_distance_m", min_pedestrian_m > 1e8 ? nlohmann::json() : nlohmann::json(min_pedestrian_m)},
          {"closest_pedestrian", closest_pedestrian},
          {"time_s", time_s},
          {"park_error_m", park_error_m},
          {"park_error_deg", park_error_deg},
          {"believed_park_error_m", believed_park_error_m},
          {"believed_park_error_deg", believed_park_error_deg},
          {"planning_ms", Quantiles(plan_ms)},
          {"speed_limited_s", limited_s},
          {"map_replans", map_replans},
          {"local_planner", LocalToJson(local)},
          {"timing",
           {{"wall_s", wall_s},
            {"real_time_factor", wall_s > 0 ? time_s / wall_s : 0.0},
            {"stage_ms_per_s", PerSecond(stage_ms, time_s)}}},
          {"states_visited", visited},
          {"transitions", states}};
}

}  // namespace specht::pipeline
