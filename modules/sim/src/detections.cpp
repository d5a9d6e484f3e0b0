#include "specht/sim/detections.h"

#include <cmath>

namespace specht::sim {
namespace {

const char* kClasses[] = {"pedestrian", "cyclist", "car"};

bool LineOfSight(const sim::World& world, sim::Vec2 from, sim::Vec2 to) {
  const double dx = to.x - from.x, dy = to.y - from.y, d = std::hypot(dx, dy);
  if (d < 1e-6) return true;
  return world.RayCast(from, std::atan2(dy, dx), d, {}) >= d - 0.05;
}

}  // namespace

SyntheticDetector::SyntheticDetector(const SyntheticDetectionOptions& options, uint64_t seed)
    : options_(options), rng_(seed * 0x9E3779B97F4A7C15ULL + 0x5eed) {}

bool SyntheticDetector::Due(const sim::Simulator& sim) const {
  const int64_t every = std::max<int64_t>(1, std::llround(1.0 / (options_.rate_hz * sim::Simulator::kStepS)));
  const int64_t step = std::llround(sim.time_s() / sim::Simulator::kStepS);
  return step % every == 0;
}

std::vector<types::Obstacle> SyntheticDetector::Detect(const sim::Simulator& sim) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  const sim::Pose2 ego = sim.ego().pose;
  std::vector<types::Obstacle> out;
  visible_.clear();
  hidden_.clear();
  auto add = [&](double x, double y, std::string cls, double sigma, double score) {
    types::Obstacle o;
    o.id = next_id_++;
    o.cls = std::move(cls);
    o.stamp = sim.stamp();
    o.x_m = x + sigma * normal(rng_);
    o.y_m = y + sigma * normal(rng_);
    o.covariance_xy = cv::Matx22d::eye() * (sigma * sigma);
    o.score = score;
    out.push_back(o);
  };
  for (const auto& a : sim.agents()) {
    const double d = std::hypot(a.pose.x - ego.x, a.pose.y - ego.y);
    if (d > options_.range_m || !LineOfSight(sim.world(), {ego.x, ego.y}, {a.pose.x, a.pose.y})) {
      hidden_.push_back(a);
      continue;
    }
    visible_.push_back(a);
    if (uniform(rng_) >= options_.detection_probability) continue;
    std::string cls = sim::Name(a.cls);
    if (uniform(rng_) < options_.class_error) {
      const int shift = 1 + static_cast<int>(uniform(rng_) * 2);
      cls = kClasses[(static_cast<int>(a.cls) + shift) % 3];
    }
    add(a.pose.x, a.pose.y, cls, options_.position_sigma_m + options_.range_sigma_fraction * d,
        0.5 + 0.5 * uniform(rng_));
    out.back().radius_m = std::max(a.length_m, a.width_m) / 2;
    out.back().length_m = a.length_m, out.back().width_m = a.width_m, out.back().yaw_rad = a.pose.yaw_rad;
  }
  std::poisson_distribution<int> false_alarms(options_.false_alarms_per_frame);
  const int n = options_.false_alarms_per_frame > 0 ? false_alarms(rng_) : 0;
  for (int i = 0; i < n; ++i) {
    const double r = options_.range_m * std::sqrt(uniform(rng_)), phi = 2 * M_PI * uniform(rng_);
    const double x = ego.x + r * std::cos(phi), y = ego.y + r * std::sin(phi);
    if (sim.world().Blocked({x, y})) continue;
    add(x, y, kClasses[static_cast<int>(uniform(rng_) * 3) % 3], options_.position_sigma_m, 0.3 + 0.3 * uniform(rng_));
  }
  return out;
}

}  // namespace specht::sim
