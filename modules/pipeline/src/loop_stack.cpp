#include "internal/loop_stack.h"

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
#include "internal/ros_recorder.h"
#include "specht/core/error.h"
#include "specht/decide/mission_state.h"
#include "specht/sim/world.h"

namespace specht::pipeline::internal {

using decide::Goal;
using decide::MissionEvent;
using decide::MissionState;
using decide::MissionStateMachine;
using decide::Transition;

namespace {

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
    grid_.insertObservation(scan, Pose3(ego));
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
  // `confirm_s`: how long perception takes to confirm the road users around the car
  // (the tracker's confirmation window): the car sets off, and drives on after a blind
  // spell, only once frames have come that long.
  Machine(const ClosedLoopConfig& c, const std::vector<Goal>& mission, uint64_t seed, double confirm_s,
          ClosedLoopResult& r)
      : c_(c), mission_(mission), r_(r), seed_(static_cast<unsigned>(seed)), confirm_s_(confirm_s) {
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
      if (frames_back_since_ < 0) frames_back_since_ = t;
      if (t - frames_back_since_ >= confirm_s_ - 1e-9) {
        char reason[96];
        std::snprintf(reason, sizeof(reason), "perception frames again for %.2f s", t - frames_back_since_);
        Handle(MissionEvent::kSensorRestored, t, reason);
      }
    }
    if (perception_late_) frames_back_since_ = -1;
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
          for (const auto& p : Corners(b)) poly.push_back(cell(p));
          cv::fillConvexPoly(obstacles, poly, cv::Scalar(1));
        }
      // A return's disc stops 0.2 m short of the car as it stands: the search needs
      // its start clear (a return at the bumper is left to the emergency stop).
      const Box car = CarBox(c_.car, pose);
      for (const auto& p : unexplained_) {
        const double radius = std::min(c_.loop.pedestrian_margin_m, PointToBox(p, car) - 0.2);
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
      if (BoxToBox(box, o.box) <= 0) return "emergency stop: " + o.Name() + " within the stopping distance";
    return "";
  }

  std::string ReturnAhead(double speed, const std::vector<cv::Point2d>& returns) const {
    if (!c_.loop.lidar_stop || std::abs(speed) < c_.tracker.stop_speed_mps) return "";
    const Box own = Stretched({0, 0, 0}, speed, Braking(speed) + c_.loop.lidar_stop_buffer_m);
    for (const auto& p : returns)
      if (PointToBox(p, own) <= 0) {
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
      const bool on_track =
          std::any_of(tracks.begin(), tracks.end(), [&](const SeenObject& a) { return PointToBox(w, a.box) < 0.3; });
      const bool known = std::any_of(unexplained_.begin(), unexplained_.end(),
                                     [&](const cv::Point2d& q) { return std::hypot(q.x - w.x, q.y - w.y) < 0.1; });
      if (!on_track && !known) unexplained_.push_back(w);
    }
  }

  // The car's box at `pose` stretched by `reach` in its direction of travel.
  Box Stretched(const plan::Pose& pose, double speed, double reach) const {
    Box box = CarBox(c_.car, pose);
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
    std::vector<Box> swept = {CarBox(c_.car, pose)};
    double along = 0;
    for (size_t i = tracker_->progress_index() + 1; i < points.size() && along < reach; ++i) {
      along += std::hypot(points[i].pose.x - points[i - 1].pose.x, points[i].pose.y - points[i - 1].pose.y);
      swept.push_back(CarBox(c_.car, points[i].pose));
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
          if (BoxToBox(box, b) < margin) return a.Name();
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
  std::shared_ptr<plan::DistanceMap> static_map_;                      // planned on
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
  double confirm_s_;
  double frames_back_since_ = -1;  // blind, frames came again from here on
};

// The believed pose against the prior map (slam/pose_check.h): every scan, its
// returns on tracks removed, scored where the car believes it took it; lost after
// lost_after_scans disagreeing scans in a row, then searched for on the map at every
// scan until found.
class LoopPoseCheck {
 public:
  LoopPoseCheck(std::shared_ptr<const mrpt::maps::COccupancyGridMap2D> prior_map, const slam::PoseCheckOptions& options)
      : prior_map_(std::move(prior_map)), check_(*prior_map_, options), monitor_(options) {}

  // `scan` (returns on tracks removed) taken at the believed box-centre pose `at`.
  void Observe(const mrpt::obs::CObservation2DRangeScan& scan, double t, LoopLocalization& where, Machine& machine) {
    mrpt::maps::CSimplePointsMap points;
    ForEachReturn(scan, {0, 0, 0}, [&](size_t, const cv::Point2d& p) { points.insertPointFast(p.x, p.y, 0); });
    const sim::Pose2 at = where.AtLatestScan();
    const mrpt::poses::CPose2D believed(at.x, at.y, at.yaw_rad);
    if (machine.state() == MissionState::kLocalizationLost) {
      const auto found = check_.Relocalize(points, believed);
      if (!found) return;
      where.Relocalize({found->pose.x(), found->pose.y(), found->pose.phi()});
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
  void ScanPose(Stamp t, const sim::Pose2& believed) { record_.Pose(t, Pose3(believed)); }
  void Step(Stamp t, const sim::Pose2& believed, const world::Snapshot& snapshot, const Perceived& seen,
            const std::vector<plan::Pose>& path) {
    believed_.push_back({t, Pose3(believed)});
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
  static std::vector<std::unique_ptr<MessageSink>> Sinks(const std::string& path) {
    std::vector<std::unique_ptr<MessageSink>> sinks;
    sinks.push_back(McapSink(path));
    return sinks;
  }
  RosRecorder record_;
  Trajectory believed_;  // at the control rate, for /trajectory
  double last_s_ = -INFINITY;
  std::shared_ptr<const mrpt::maps::COccupancyGridMap2D> map_;  // the static layer recorded last
};

// Runs `f`, its wall-clock time added to `ms` (the report's timing per stage; never
// a pass/fail figure).
template <class F>
auto Timed(double& ms, F&& f) {
  struct Add {
    double& ms;
    std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
    ~Add() { ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count(); }
  } add{ms};
  return f();
}

// How long perception takes to confirm the road users around the car: the tracker's
// confirmation window at the frame rate (none for the oracle).
double ConfirmSeconds(const sim::Scenario& scenario, const ClosedLoopConfig& config) {
  if (config.loop.perception == "truth") return 0.0;
  const double frame_rate_hz = config.loop.perception == "camera" ? scenario.stereo->rate_hz : config.detection.rate_hz;
  return config.tracking.confirm_window / frame_rate_hz;
}

}  // namespace

class LoopStack::Impl {
 public:
  Impl(const sim::Scenario& scenario, uint64_t seed, const std::vector<Goal>& mission, const ClosedLoopConfig& config,
       Stamp start, ClosedLoopResult& r)
      : scenario_(scenario),
        config_(config),
        r_(r),
        world_(config.world),
        slam_config_(SlamConfig(config)),
        where_(config.loop.localization, scenario, slam_config_,
               {config.loop.kidnap_at_s, config.loop.kidnap_m, config.loop.kidnap_deg}),
        perceive_(config.loop.perception, config.tracking, world_, config.camera),
        site_grid_(sim::World(scenario).TrueGrid(kPlanningResolutionM)),
        warmup_s_(ConfirmSeconds(scenario, config)),
        machine_(config, mission, seed, warmup_s_, r),
        centre_from_axle_{scenario.ego.model.PivotAhead(), 0, 0} {
    const ClosedLoopOptions& loop = config.loop;
    if (loop.map_source == "lidar")
      lidar_.emplace(plan::DistanceMap::FromGrid(site_grid_));  // nothing seen yet
    else  // a prior map of the site: a mapping drive's, or the scenario's true grid
      world_.SetStaticMap(config.slam.site_map ? config.slam.site_map->grid : site_grid_, start);
    // The pose check needs a prior map, and a pose that can be wrong.
    if (config.pose_check.enabled && !lidar_ && (loop.localization != "truth" || loop.kidnap_at_s >= 0))
      pose_check_.emplace(world_.snapshot()->static_map, config.pose_check);
    if (!config.mcap.empty()) record_.emplace(config.mcap, config.slam.grid);
    snapshot_ = world_.snapshot();
  }

  void OracleEgo(const sim::Pose2& truth) { where_.Oracle(truth); }
  std::vector<types::Track> OracleAgents(const std::vector<sim::AgentTruth>& agents, Stamp stamp) {
    return Timed(r_.stage_ms["perceive"], [&] { return perceive_.Oracle(agents, stamp); });
  }
  std::vector<types::Track> Detections(std::vector<types::Obstacle> in_car, Stamp stamp) {
    return Timed(r_.stage_ms["perceive"],
                 [&] { return perceive_.Detections(std::move(in_car), stamp, where_.Believed()); });
  }
  void Tracked(std::vector<types::Track> tracks, std::vector<types::Obstacle> obstacles, Stamp stamp) {
    Timed(r_.stage_ms["perceive"], [&] { perceive_.Tracked(std::move(tracks), std::move(obstacles), stamp); });
  }
  sim::Pose2 Localized() const { return where_.Believed(); }
  std::vector<types::Track> Camera(const mrpt::obs::CObservationStereoImages& frame, Stamp stamp) {
    return Timed(r_.stage_ms["perceive"], [&] { return perceive_.Camera(frame, stamp, where_.Believed()); });
  }

  // Scans reach SLAM and the LiDAR map without their returns on tracked road users:
  // a car driving ahead along a street whose walls leave the scan matcher free along
  // it would carry the car's believed pose with it.
  void Observe(Stamp t, double t_s, const mrpt::obs::CObservation::Ptr& obs) {
    Timed(r_.stage_ms["localize"], [&] {
      if (record_) record_->Observation(t, obs);
      const auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs);
      if (!scan) return where_.Observe(t, obs);
      returns_.clear();
      if (config_.loop.lidar_stop)
        ForEachReturn(*scan, centre_from_axle_, [&](size_t, const cv::Point2d& p) { returns_.push_back(p); });
      if (!lidar_ && !where_.UsesObservations() && !pose_check_) return;  // nothing reads the scan
      const auto tracks = PerceivedFrom(*world_.snapshot()).tracks;
      const auto kept = WithoutReturnsOn(*scan, where_.Believed(), tracks);
      where_.Observe(t, kept);
      if (record_) record_->ScanPose(t, where_.AtLatestScan());
      if (lidar_) lidar_->Insert(*kept, where_.AtLatestScan());
      if (pose_check_) pose_check_->Observe(*kept, t_s, where_, machine_);
    });
  }

  plan::Command Control(double t, Stamp stamp, double speed, double steer) {
    const ClosedLoopOptions& loop = config_.loop;
    if (lidar_ && t - map_updated_s_ >= 1.0 / loop.map_update_hz - 1e-9) {
      if (lidar_->TakeChanged()) world_.SetStaticMap(lidar_->grid(), stamp);
      map_updated_s_ = t;
    }
    snapshot_ = world_.snapshot();
    machine_.SyncMap(*snapshot_, t);
    where_.Tick(t);
    const plan::Pose believed = EgoRearAxle(scenario_, where_.Believed());
    const double perception_age_s = SecondsBetween(snapshot_->tracks_stamp, stamp);
    const Perceived seen = PerceivedFrom(*snapshot_, perception_age_s);
    tracks_seen_ = static_cast<int>(seen.tracks.size());
    const plan::Command cmd = Timed(r_.stage_ms["decide_and_plan"], [&] {
      return t < warmup_s_ ? plan::Command{}
                           : machine_.Step(t, believed, speed, steer, seen, returns_, perception_age_s);
    });
    if (record_)
      Timed(r_.stage_ms["mcap"],
            [&] { record_->Step(stamp, where_.Believed(), *snapshot_, seen, machine_.PathAhead()); });
    return cmd;
  }

  void TimeLimit(double t, const std::string& reason) { machine_.Handle(MissionEvent::kTimeLimit, t, reason); }
  bool Final() const { return machine_.Final(); }
  sim::Pose2 Believed() const { return where_.Believed(); }
  const world::Snapshot& snapshot() const { return *snapshot_; }
  int tracks_seen() const { return tracks_seen_; }
  std::string state() const { return decide::Name(machine_.state()); }
  bool OnLocalPath() const { return machine_.OnLocalPath(); }
  std::vector<plan::Pose> PathAhead() const { return machine_.PathAhead(); }

  void Finish(Stamp end) {
    if (record_) {
      const auto last = world_.snapshot();
      record_->Finish(last->static_map ? *last->static_map : site_grid_, end);
      r_.mcap = std::filesystem::path(config_.mcap).filename().string();
    }
    r_.transitions = machine_.transitions();
    r_.stack = config_.loop.Stack();
    r_.static_layer = lidar_ ? "lidar" : config_.slam.site_map ? "site map" : "true grid";
    r_.localization = where_.ToJson();
    if (pose_check_) r_.localization["pose_check"] = pose_check_->ToJson();
    r_.perception = perceive_.ToJson();
    slam::GridOptions drawn = config_.slam.grid;
    drawn.resolution_m = kPlanningResolutionM;
    r_.drawn_map = where_.DrawnMap(scenario_.name, drawn);
  }

 private:
  static LoopSlamConfig SlamConfig(const ClosedLoopConfig& config) {
    LoopSlamConfig slam = config.slam;
    slam.survey_spacing_m = config.loop.survey_spacing_m;
    // The simulated car's odometry is good to about 1 % of a step (sensors.odometry); the
    // scan_matching defaults are sized for logs whose odometry drifts tens of metres.
    if (config.loop.good_odometry) slam.matching = slam::GoodOdometry(slam.matching);
    return slam;
  }

  const sim::Scenario& scenario_;
  const ClosedLoopConfig& config_;
  ClosedLoopResult& r_;
  world::WorldModel world_;
  LoopSlamConfig slam_config_;
  LoopLocalization where_;
  LoopPerception perceive_;
  mrpt::maps::COccupancyGridMap2D site_grid_;  // the site's true static grid: the truth stack's prior map
  const double warmup_s_;                      // ConfirmSeconds: the car sets off after this
  Machine machine_;
  std::optional<LidarMap> lidar_;
  std::optional<LoopPoseCheck> pose_check_;
  std::optional<LoopRecording> record_;  // the run as MCAP (config.mcap)
  std::vector<cv::Point2d> returns_;     // the latest scan's, rear-axle frame (the emergency check's)
  sim::Pose2 centre_from_axle_;
  double map_updated_s_ = -INFINITY;
  std::shared_ptr<const world::Snapshot> snapshot_;  // the latest control step's
  int tracks_seen_ = 0;
};

LoopStack::LoopStack(const sim::Scenario& scenario, uint64_t seed, const std::vector<Goal>& mission,
                     const ClosedLoopConfig& config, Stamp start, ClosedLoopResult& result)
    : impl_(std::make_unique<Impl>(scenario, seed, mission, config, start, result)) {}
LoopStack::~LoopStack() = default;
void LoopStack::OracleEgo(const sim::Pose2& truth) { impl_->OracleEgo(truth); }
std::vector<types::Track> LoopStack::OracleAgents(const std::vector<sim::AgentTruth>& agents, Stamp stamp) {
  return impl_->OracleAgents(agents, stamp);
}
void LoopStack::Observe(Stamp t, double t_s, const mrpt::obs::CObservation::Ptr& observation) {
  impl_->Observe(t, t_s, observation);
}
std::vector<types::Track> LoopStack::Detections(std::vector<types::Obstacle> in_car, Stamp stamp) {
  return impl_->Detections(std::move(in_car), stamp);
}
void LoopStack::Tracked(std::vector<types::Track> tracks, std::vector<types::Obstacle> obstacles, Stamp stamp) {
  impl_->Tracked(std::move(tracks), std::move(obstacles), stamp);
}
sim::Pose2 LoopStack::Localized() const { return impl_->Localized(); }
std::vector<types::Track> LoopStack::Camera(const mrpt::obs::CObservationStereoImages& frame, Stamp stamp) {
  return impl_->Camera(frame, stamp);
}
plan::Command LoopStack::Control(double t_s, Stamp stamp, double speed_mps, double steer_rad) {
  return impl_->Control(t_s, stamp, speed_mps, steer_rad);
}
void LoopStack::TimeLimit(double t_s, const std::string& reason) { impl_->TimeLimit(t_s, reason); }
bool LoopStack::Final() const { return impl_->Final(); }
sim::Pose2 LoopStack::Believed() const { return impl_->Believed(); }
const world::Snapshot& LoopStack::snapshot() const { return impl_->snapshot(); }
int LoopStack::tracks_seen() const { return impl_->tracks_seen(); }
std::string LoopStack::state() const { return impl_->state(); }
bool LoopStack::OnLocalPath() const { return impl_->OnLocalPath(); }
std::vector<plan::Pose> LoopStack::PathAhead() const { return impl_->PathAhead(); }
void LoopStack::Finish(Stamp end) { impl_->Finish(end); }

}  // namespace specht::pipeline::internal
