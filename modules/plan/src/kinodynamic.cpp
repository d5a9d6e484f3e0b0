#include "specht/plan/kinodynamic.h"

#include <ompl/base/OptimizationObjective.h>
#include <ompl/base/ProjectionEvaluator.h>
#include <ompl/base/goals/GoalSampleableRegion.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/base/spaces/SE2StateSpace.h>
#include <ompl/control/PathControl.h>
#include <ompl/control/SpaceInformation.h>
#include <ompl/control/planners/kpiece/KPIECE1.h>
#include <ompl/control/planners/rrt/RRT.h>
#include <ompl/control/planners/sst/SST.h>
#include <ompl/control/spaces/RealVectorControlSpace.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include <chrono>
#include <cmath>
#include <mutex>

#include "specht/core/error.h"

namespace specht::plan {

std::vector<std::string> KinodynamicOptions::Relations() const {
  std::vector<std::string> p;
  if (min_control_steps > max_control_steps) p.push_back("min_control_steps must not exceed max_control_steps");
  if (integration_step_s > control_step_s) p.push_back("integration_step_s must not exceed control_step_s");
  return p;
}

namespace {

namespace ob = ompl::base;
namespace oc = ompl::control;
using Clock = std::chrono::steady_clock;

// The state's parts: SE2 (x, y, θ); "drive" = (δ, v); "log" = (t, metres driven,
// metres reversed, gear changes, last direction ±1 or 0) — the log has no weight in distances, it only
// makes motion costs exact (the difference of two logs) and carries the time
// the moving-obstacle check needs.
enum Drive { kSteer = 0, kSpeed = 1 };
enum Log { kTime = 0, kDriven = 1, kReversed = 2, kGearChanges = 3, kDirection = 4, kLogSize = 5 };

const ob::SE2StateSpace::StateType& Se2(const ob::State* s) {
  return *s->as<ob::CompoundState>()->as<ob::SE2StateSpace::StateType>(0);
}
ob::SE2StateSpace::StateType& Se2(ob::State* s) {
  return *s->as<ob::CompoundState>()->as<ob::SE2StateSpace::StateType>(0);
}
const double* Values(const ob::State* s, int part) {
  return s->as<ob::CompoundState>()->as<ob::RealVectorStateSpace::StateType>(part)->values;
}
double* Values(ob::State* s, int part) {
  return s->as<ob::CompoundState>()->as<ob::RealVectorStateSpace::StateType>(part)->values;
}
Pose PoseOf(const ob::State* s) { return {Se2(s).getX(), Se2(s).getY(), Se2(s).getYaw()}; }

// The compound space with its distance written out: OMPL's generic compound
// distance would also compute the log's, weighted 0, on every nearest-neighbour
// query (more than half the planning time). Same value, same order of operations:
//   d = 1·(|Δxy| + ½·|Δθ|) + drive_weight·|Δ(δ, v)|
class CarStateSpace : public ob::CompoundStateSpace {
 public:
  static constexpr double kDriveWeight = 0.2;
  double distance(const ob::State* a, const ob::State* b) const override {
    const auto &pa = Se2(a), &pb = Se2(b);
    double turn = std::abs(pa.getYaw() - pb.getYaw());
    if (turn > M_PI) turn = 2 * M_PI - turn;
    const double dx = pa.getX() - pb.getX(), dy = pa.getY() - pb.getY();
    const double se2 = std::sqrt(dx * dx + dy * dy) + 0.5 * turn;
    const double* da = Values(a, 1);
    const double* db = Values(b, 1);
    const double drive = std::sqrt((da[0] - db[0]) * (da[0] - db[0]) + (da[1] - db[1]) * (da[1] - db[1]));
    return se2 + kDriveWeight * drive;
  }
};

// The bicycle model of the header, integrated in sub-steps.
class BicyclePropagator : public oc::StatePropagator {
 public:
  BicyclePropagator(const oc::SpaceInformationPtr& si, const CarOptions& car, const KinodynamicOptions& o)
      : oc::StatePropagator(si),
        wheelbase_(car.wheelbase_m),
        max_steer_(car.max_steer_deg * M_PI / 180 * o.steer_fraction),
        max_accel_(car.max_accel_mps2),
        step_(o.integration_step_s) {}

  void propagate(const ob::State* from, const oc::Control* control, double duration, ob::State* to) const override {
    const double* u = control->as<oc::RealVectorControlSpace::ControlType>()->values;
    const double target = u[0], steer_rate = u[1];
    double x = Se2(from).getX(), y = Se2(from).getY(), theta = Se2(from).getYaw();
    double steer = Values(from, 1)[kSteer], v = Values(from, 1)[kSpeed];
    double log[kLogSize];
    std::copy(Values(from, 2), Values(from, 2) + kLogSize, log);
    const int n = std::max(1, static_cast<int>(std::ceil(duration / step_ - 1e-9)));
    const double dt = duration / n;
    for (int i = 0; i < n; ++i) {
      steer = std::clamp(steer + steer_rate * dt, -max_steer_, max_steer_);
      const double v_next = v + std::clamp(target - v, -max_accel_ * dt, max_accel_ * dt);
      v = v_next;
      const double direction = v > 0 ? 1 : v < 0 ? -1 : 0;
      if (direction != 0 && log[kDirection] != direction) {
        if (log[kDirection] != 0) log[kGearChanges] += 1;
        log[kDirection] = direction;
      }
      // Midpoint rule: the chord of a step points along the mean heading, so the
      // angle between consecutive chords over their mean length is the curvature
      // driven (what Path::MaxCurvature measures).
      const double turn = v * std::tan(steer) / wheelbase_ * dt;
      x += v * std::cos(theta + turn / 2) * dt, y += v * std::sin(theta + turn / 2) * dt;
      theta += turn;
      log[kTime] += dt, log[kDriven] += std::abs(v) * dt;
      if (v < 0) log[kReversed] += -v * dt;
    }
    Se2(to).setXY(x, y), Se2(to).setYaw(std::remainder(theta, 2 * M_PI));
    Values(to, 1)[kSteer] = steer, Values(to, 1)[kSpeed] = v;
    std::copy(log, log + kLogSize, Values(to, 2));
  }

 private:
  double wheelbase_, max_steer_, max_accel_, step_;
};

// The footprint against the map and, at the state's time, the moving obstacles.
class Validity : public ob::StateValidityChecker {
 public:
  Validity(const ob::SpaceInformationPtr& si, std::shared_ptr<const DistanceMap> map, const CarOptions& car,
           const std::vector<MovingObstacle>& obstacles)
      : ob::StateValidityChecker(si), map_(std::move(map)), discs_(car.Discs()), obstacles_(obstacles) {}

  bool isValid(const ob::State* s) const override {
    const Pose p = PoseOf(s);
    if (!map_->Contains(p.x, p.y) || !map_->Free(discs_, p)) return false;
    return ClearOfMovingObstacles(discs_, p, obstacles_, Values(s, 2)[kTime]);
  }

 private:
  std::shared_ptr<const DistanceMap> map_;
  DiscCover discs_;
  std::vector<MovingObstacle> obstacles_;
};

// The cost of the header: exact differences of the state logs, plus clearance.
class Objective : public ob::OptimizationObjective {
 public:
  Objective(const ob::SpaceInformationPtr& si, const KinodynamicOptions& o, std::shared_ptr<const DistanceMap> map,
            const CarOptions& car)
      : ob::OptimizationObjective(si), o_(o), map_(std::move(map)), discs_(car.Discs()) {
    description_ = "specht kinodynamic: " + o.objective + " + reversing, gear changes, clearance";
  }
  ob::Cost stateCost(const ob::State*) const override { return identityCost(); }
  ob::Cost motionCost(const ob::State* a, const ob::State* b) const override {
    const double* la = Values(a, 2);
    const double* lb = Values(b, 2);
    const double driven = lb[kDriven] - la[kDriven], reversed = lb[kReversed] - la[kReversed];
    const double base = o_.objective == "time" ? lb[kTime] - la[kTime] : driven;
    const double reverse_share = driven > 0 ? reversed / driven : 0;
    double c = base * (1 + (o_.reverse_penalty - 1) * reverse_share);
    c += o_.gear_change_penalty * (lb[kGearChanges] - la[kGearChanges]);
    if (o_.clearance_weight > 0)
      c += o_.clearance_weight * driven * std::max(0.0, 1 - Clearance(b) / o_.clearance_target_m);
    return ob::Cost(c);
  }

 private:
  double Clearance(const ob::State* s) const {
    const Pose p = PoseOf(s);
    double least = INFINITY;
    for (const double d : discs_.offsets)
      least = std::min(least, map_->Distance(p.x + std::cos(p.theta) * d, p.y + std::sin(p.theta) * d) - discs_.radius);
    return std::max(0.0, least);
  }
  KinodynamicOptions o_;
  std::shared_ptr<const DistanceMap> map_;
  DiscCover discs_;
};

// Goal: a pose. distanceGoal folds the heading error into metres so that
// "satisfied" (distance ≤ threshold = goal_tolerance_m) needs both.
class PoseGoal : public ob::GoalSampleableRegion {
 public:
  PoseGoal(const ob::SpaceInformationPtr& si, const Pose& goal, const KinodynamicOptions& o)
      : ob::GoalSampleableRegion(si),
        goal_(goal),
        metres_per_rad_(o.goal_tolerance_m / (o.goal_heading_tolerance_deg * M_PI / 180)) {
    setThreshold(o.goal_tolerance_m);
  }
  double distanceGoal(const ob::State* s) const override {
    const Pose p = PoseOf(s);
    return std::max(std::hypot(p.x - goal_.x, p.y - goal_.y),
                    std::abs(std::remainder(p.theta - goal_.theta, 2 * M_PI)) * metres_per_rad_);
  }
  void sampleGoal(ob::State* s) const override {
    Se2(s).setXY(goal_.x, goal_.y), Se2(s).setYaw(goal_.theta);
    std::fill(Values(s, 1), Values(s, 1) + 2, 0.0);
    std::fill(Values(s, 2), Values(s, 2) + kLogSize, 0.0);
  }
  unsigned int maxSampleCount() const override { return 1; }

 private:
  Pose goal_;
  double metres_per_rad_;
};

// KPIECE1 grids the state space through a projection: the rear axle's (x, y).
class XYProjection : public ob::ProjectionEvaluator {
 public:
  XYProjection(const ob::StateSpace* space, double cell) : ob::ProjectionEvaluator(space), cell_(cell) {}
  unsigned int getDimension() const override { return 2; }
  void defaultCellSizes() override { cellSizes_ = {cell_, cell_}; }
  void project(const ob::State* s, Eigen::Ref<Eigen::VectorXd> out) const override {
    out[0] = Se2(s).getX(), out[1] = Se2(s).getY();
  }

 private:
  double cell_;
};

// Guided sampling: with probability `bias` a state near a random point of the
// guide path (Gaussian, σ in metres and σ_θ = 0.3 rad), otherwise uniform — the
// global search's path tells the tree where the passages are.
class GuidedSampler : public ob::StateSampler {
 public:
  GuidedSampler(const ob::StateSpace* space, std::vector<Pose> guide, double bias, double sigma_m)
      : ob::StateSampler(space),
        uniform_(space->allocDefaultStateSampler()),
        guide_(std::move(guide)),
        bias_(bias),
        sigma_(sigma_m) {}
  void sampleUniform(ob::State* s) override {
    uniform_->sampleUniform(s);
    if (guide_.empty() || rng_.uniform01() >= bias_) return;
    const Pose& p = guide_[rng_.uniformInt(0, static_cast<int>(guide_.size()) - 1)];
    Se2(s).setXY(p.x + rng_.gaussian(0, sigma_), p.y + rng_.gaussian(0, sigma_));
    Se2(s).setYaw(std::remainder(p.theta + rng_.gaussian(0, 0.3), 2 * M_PI));
  }
  void sampleUniformNear(ob::State* s, const ob::State* near, double distance) override {
    uniform_->sampleUniformNear(s, near, distance);
  }
  void sampleGaussian(ob::State* s, const ob::State* mean, double stddev) override {
    uniform_->sampleGaussian(s, mean, stddev);
  }

 private:
  ob::StateSamplerPtr uniform_;
  std::vector<Pose> guide_;
  double bias_, sigma_;
};

// OMPL 1.5's SST deletes its witnesses without freeing the state and control each
// one allocated (freeMemory: `delete witness`): thousands per call, found by
// LeakSanitizer. This frees them first; the base class then deletes the husks.
class WitnessFreeingSst : public oc::SST {
 public:
  using oc::SST::SST;
  ~WitnessFreeingSst() override { FreeWitnessStates(); }
  void clear() override {
    FreeWitnessStates();
    oc::SST::clear();
  }

 private:
  void FreeWitnessStates() {
    if (!witnesses_) return;
    std::vector<Motion*> witnesses;
    witnesses_->list(witnesses);
    for (Motion* w : witnesses) {
      if (w->state_) si_->freeState(w->state_);
      if (w->control_) siC_->freeControl(w->control_);
      w->state_ = nullptr, w->control_ = nullptr;
    }
  }
};

void SeedOnce(int seed) {
  static std::once_flag once;
  std::call_once(once, [seed] {
    ompl::msg::setLogLevel(ompl::msg::LOG_WARN);
    ompl::RNG::setSeed(static_cast<std::uint_fast32_t>(seed));
  });
}

// The speeds a plan may drive at, by `directions`: reversing, forward or both.
std::pair<double, double> SpeedRange(const KinodynamicOptions& o, const CarOptions& car) {
  return {o.directions == "forward" ? 0.0 : -car.max_reverse_mps, o.directions == "reverse" ? 0.0 : car.max_speed_mps};
}

}  // namespace

bool ClearOfMovingObstacles(const DiscCover& discs, const Pose& pose, const std::vector<MovingObstacle>& obstacles,
                            double t_s) {
  const double c = std::cos(pose.theta), s = std::sin(pose.theta);
  for (const MovingObstacle& o : obstacles) {
    const double ox = o.x + o.vx * t_s, oy = o.y + o.vy * t_s, need = discs.radius + o.radius_m + discs.margin;
    for (const double d : discs.offsets)
      if (std::hypot(pose.x + c * d - ox, pose.y + s * d - oy) < need) return false;
  }
  return true;
}

// OMPL 1.5 reseeds its seed generator on every setSeed, but reports it as an error
// once numbers were drawn (its concern: a seed changed mid-run): it is not one here.
void KinodynamicPlanner::Reseed(unsigned seed) {
  SeedOnce(static_cast<int>(seed));
  const ompl::msg::LogLevel level = ompl::msg::getLogLevel();
  ompl::msg::setLogLevel(ompl::msg::LOG_NONE);
  ompl::RNG::setSeed(std::max(1u, seed));
  ompl::msg::setLogLevel(level);
}

struct KinodynamicPlanner::Impl {
  KinodynamicOptions o;
  CarOptions car;
  std::shared_ptr<const DistanceMap> map;
  std::shared_ptr<CarStateSpace> space;
  std::shared_ptr<oc::RealVectorControlSpace> controls;
};

KinodynamicPlanner::KinodynamicPlanner(const KinodynamicOptions& options, const CarOptions& car,
                                       std::shared_ptr<const DistanceMap> map)
    : impl_(std::make_unique<Impl>()) {
  SeedOnce(options.seed);
  Impl& m = *impl_;
  m.o = options, m.car = car, m.map = std::move(map);
  auto se2 = std::make_shared<ob::SE2StateSpace>();
  ob::RealVectorBounds xy(2);
  xy.setLow(0, m.map->origin_x()), xy.setHigh(0, m.map->origin_x() + m.map->cols() * m.map->resolution());
  xy.setLow(1, m.map->origin_y()), xy.setHigh(1, m.map->origin_y() + m.map->rows() * m.map->resolution());
  se2->setBounds(xy);
  const double max_steer = car.max_steer_deg * M_PI / 180 * options.steer_fraction;
  auto drive = std::make_shared<ob::RealVectorStateSpace>(2);
  ob::RealVectorBounds drive_bounds(2);
  drive_bounds.setLow(kSteer, -max_steer), drive_bounds.setHigh(kSteer, max_steer);
  drive_bounds.setLow(kSpeed, -car.max_reverse_mps), drive_bounds.setHigh(kSpeed, car.max_speed_mps);
  drive->setBounds(drive_bounds);
  auto log = std::make_shared<ob::RealVectorStateSpace>(kLogSize);
  log->setBounds(-1, 1e9);
  m.space = std::make_shared<CarStateSpace>();
  // Distances: position and heading (SE2's own weighting), steering and speed a
  // little (nearby states that could not follow each other are not near), the log
  // not at all.
  m.space->addSubspace(se2, 1.0);
  m.space->addSubspace(drive, CarStateSpace::kDriveWeight);
  m.space->addSubspace(log, 0.0);
  m.space->registerDefaultProjection(std::make_shared<XYProjection>(m.space.get(), 1.0));
  m.controls = std::make_shared<oc::RealVectorControlSpace>(m.space, 2);
  ob::RealVectorBounds u(2);
  const double steer_rate = car.max_steer_rate_deg_s * M_PI / 180;
  const auto [slowest, fastest] = SpeedRange(options, car);
  u.setLow(0, slowest), u.setHigh(0, fastest);
  u.setLow(1, -steer_rate), u.setHigh(1, steer_rate);
  m.controls->setBounds(u);
}
KinodynamicPlanner::~KinodynamicPlanner() = default;

KinodynamicResult KinodynamicPlanner::Plan(const Pose& start, const Pose& goal,
                                           const std::vector<MovingObstacle>& obstacles, const Path* guide,
                                           const StartMotion& motion) {
  Impl& m = *impl_;
  const auto t0 = Clock::now();
  CheckEndpoint(*m.map, m.car, start, "start");
  CheckEndpoint(*m.map, m.car, goal, "goal");
  KinodynamicResult result;
  result.planner = m.o.planner;

  std::vector<Pose> guide_poses;
  if (guide && m.o.guide_bias > 0)
    for (const PathPoint& p : guide->points) guide_poses.push_back(p.pose);
  const double bias = m.o.guide_bias, sigma = m.o.guide_sigma_m;
  m.space->setStateSamplerAllocator([guide_poses, bias, sigma](const ob::StateSpace* space) {
    return std::make_shared<GuidedSampler>(space, guide_poses, bias, sigma);
  });
  auto si = std::make_shared<oc::SpaceInformation>(m.space, m.controls);
  si->setStatePropagator(std::make_shared<BicyclePropagator>(si, m.car, m.o));
  si->setStateValidityChecker(std::make_shared<Validity>(si, m.map, m.car, obstacles));
  si->setPropagationStepSize(m.o.control_step_s);
  si->setMinMaxControlDuration(m.o.min_control_steps, m.o.max_control_steps);
  si->setup();

  ob::ScopedState<> s(m.space);
  Se2(s.get()).setXY(start.x, start.y), Se2(s.get()).setYaw(std::remainder(start.theta, 2 * M_PI));
  const double max_steer = m.car.max_steer_deg * M_PI / 180 * m.o.steer_fraction;
  Values(s.get(), 1)[kSteer] = std::clamp(motion.steer_rad, -max_steer, max_steer);
  const auto [slowest, fastest] = SpeedRange(m.o, m.car);
  Values(s.get(), 1)[kSpeed] = std::clamp(motion.speed_mps, slowest, fastest);
  std::fill(Values(s.get(), 2), Values(s.get(), 2) + kLogSize, 0.0);
  // The static map passed CheckEndpoint; a moving obstacle may still cover the
  // start (OMPL would only log an error and return nothing).
  if (!si->isValid(s.get())) {
    result.failure = "the start lies within a moving obstacle";
    result.milliseconds = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    return result;
  }
  auto pdef = std::make_shared<ob::ProblemDefinition>(si);
  pdef->addStartState(s);
  pdef->setGoal(std::make_shared<PoseGoal>(si, Pose{goal.x, goal.y, std::remainder(goal.theta, 2 * M_PI)}, m.o));
  auto objective = std::make_shared<Objective>(si, m.o, m.map, m.car);
  pdef->setOptimizationObjective(objective);

  ob::PlannerPtr planner;
  if (m.o.planner == "sst") {
    auto sst = std::make_shared<WitnessFreeingSst>(si);
    sst->setGoalBias(m.o.goal_bias);
    sst->setSelectionRadius(m.o.sst_selection_radius);
    sst->setPruningRadius(m.o.sst_pruning_radius);
    planner = sst;
  } else if (m.o.planner == "rrt") {
    auto rrt = std::make_shared<oc::RRT>(si);
    rrt->setGoalBias(m.o.goal_bias);
    planner = rrt;
  } else {
    auto kpiece = std::make_shared<oc::KPIECE1>(si);
    kpiece->setGoalBias(m.o.goal_bias);
    planner = kpiece;
  }
  planner->setProblemDefinition(pdef);
  planner->setup();

  // SST stops early only once a solution satisfies the objective: any finite cost
  // does when the first solution is wanted. RRT and KPIECE1 stop at their first.
  if (m.o.stop_at_first_solution)
    objective->setCostThreshold(ob::Cost(INFINITY));
  else
    objective->setCostThreshold(ob::Cost(-INFINITY));
  // One condition per call: the budget counts from the call's start, less the
  // share kept for the wrap-up — extracting the path and freeing the tree grow with
  // the tree, so a fixed share of the budget, not a fixed time, keeps every call
  // within it; the iteration counter is evaluated once per planner iteration.
  constexpr double kWrapUpShare = 0.15;
  long iterations = 0;
  const double budget_s = std::max(
      0.0, (1 - kWrapUpShare) * m.o.time_budget_ms / 1e3 - std::chrono::duration<double>(Clock::now() - t0).count());
  const ob::PlannerTerminationCondition ptc = ob::plannerOrTerminationCondition(
      ob::timedPlannerTerminationCondition(budget_s), ob::PlannerTerminationCondition([&] {
        ++iterations;
        return m.o.max_iterations > 0 && iterations >= m.o.max_iterations;
      }));
  planner->solve(ptc);
  result.expansions = iterations;

  if (pdef->hasSolution()) {
    auto& control_path = *pdef->getSolutionPath()->as<oc::PathControl>();
    result.duration_s = control_path.length();
    for (size_t i = 1; i < control_path.getStateCount(); ++i)  // OMPL's cost() is for geometric paths only
      result.cost += objective->motionCost(control_path.getState(i - 1), control_path.getState(i)).value();
    result.approximate = pdef->hasApproximateSolution();
    result.goal_distance_m = pdef->getGoal()->as<PoseGoal>()->distanceGoal(control_path.getStates().back());
    // Re-drive every control in integration steps: a dense path (≤ v_max ·
    // integration_step_s apart) with its cusps where the speed crosses zero.
    const auto& propagator = *si->getStatePropagator();
    ob::ScopedState<> at(m.space), next(m.space);
    int direction = 1;
    const auto emit = [&](const ob::State* st) {
      const double v = Values(st, 1)[kSpeed];
      if (v != 0) direction = v > 0 ? 1 : -1;
      const Pose p = PoseOf(st);
      auto& pts = result.path.points;
      if (!pts.empty() && std::hypot(p.x - pts.back().pose.x, p.y - pts.back().pose.y) < 1e-4) return;
      pts.push_back({p, direction});
      result.times_s.push_back(Values(st, 2)[kTime]);
    };
    at = control_path.getState(0);
    emit(at.get());
    for (size_t i = 0; i < control_path.getControlCount(); ++i) {
      const double duration = control_path.getControlDuration(i);
      const int n = std::max(1, static_cast<int>(std::ceil(duration / m.o.integration_step_s - 1e-9)));
      for (int k = 0; k < n; ++k) {
        propagator.propagate(at.get(), control_path.getControl(i), duration / n, next.get());
        std::swap(at, next);
        emit(at.get());
      }
    }
    // The start point takes its first motion's direction.
    if (result.path.points.size() > 1) result.path.points[0].direction = result.path.points[1].direction;
  }
  result.found = pdef->hasExactSolution();
  // Free the tree within the call (and its budget), not when the caller returns.
  planner.reset(), pdef.reset();
  if (!result.found)
    result.failure = result.approximate ? "no exact solution within the budget (closest " +
                                              std::to_string(result.goal_distance_m) + " m from the goal)"
                                        : "no solution within the budget";
  result.milliseconds = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  return result;
}

}  // namespace specht::plan
