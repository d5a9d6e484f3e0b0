#include "specht/world/world_model.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "specht/core/error.h"

namespace specht::world {

using types::CostGrid;
using types::Obstacle;
using types::Track;

namespace {

// "class=metres" entries; problems reported by Relations().
std::vector<std::pair<std::string, double>> Margins(const std::vector<std::string>& entries,
                                                    std::vector<std::string>* problems) {
  return params::ParseNumberAssignments(
      entries, "class_margins", [](double m) { return m >= 0; }, "a distance ≥ 0", problems);
}

// Raises `cost` around a centre: lethal within `core_m`, inscribed within core +
// footprint, then the decaying cost to core + footprint + margin.
void StampCircle(cv::Mat& cost, const CostGrid& grid, double x, double y, double core_m, double footprint_m,
                 double margin_m, double decay) {
  const double reach = core_m + footprint_m + margin_m;
  int c0, r0, c1, r1;
  grid.Cell(x - reach, y - reach, c0, r0);
  grid.Cell(x + reach, y + reach, c1, r1);
  c0 = std::clamp(c0, 0, cost.cols - 1), c1 = std::clamp(c1, 0, cost.cols - 1);
  r0 = std::clamp(r0, 0, cost.rows - 1), r1 = std::clamp(r1, 0, cost.rows - 1);
  for (int r = r0; r <= r1; ++r) {
    for (int c = c0; c <= c1; ++c) {
      const cv::Point2d p = grid.Centre(c, r);
      const double d = std::hypot(p.x - x, p.y - y);
      if (d > reach) continue;
      uint8_t value;
      if (d <= core_m)
        value = CostGrid::kLethal;
      else if (d <= core_m + footprint_m)
        value = CostGrid::kInscribed;
      else
        value = static_cast<uint8_t>(std::max(1.0, 252.0 * std::exp(-decay * (d - core_m - footprint_m))));
      uint8_t& cell = cost.at<uint8_t>(r, c);
      cell = std::max(cell, value);
    }
  }
}

}  // namespace

std::vector<std::string> WorldModelOptions::Relations() const {
  std::vector<std::string> problems;
  Margins(class_margins, &problems);
  if (free_probability >= occupied_probability)
    problems.push_back("free_probability must be below occupied_probability");
  return problems;
}

double WorldModelOptions::MarginFor(const std::string& cls) const {
  double other = 0;
  for (const auto& [name, margin] : Margins(class_margins, nullptr)) {
    if (name == cls) return margin;
    if (name == "other") other = margin;
  }
  return other;
}

nlohmann::json Snapshot::ToJson() const {
  nlohmann::json j;
  j["version"] = version;
  j["stamp_s"] = stamp.Seconds();
  j["layer_stamps_s"] = {{"static", static_stamp.Seconds()},
                         {"obstacles", obstacles_stamp.Seconds()},
                         {"tracks", tracks_stamp.Seconds()},
                         {"octree", octree_stamp.Seconds()}};
  if (static_map)
    j["static_map"] = {{"cells", {static_map->getSizeX(), static_map->getSizeY()}},
                       {"resolution_m", static_map->getResolution()},
                       {"origin_m", {static_map->getXMin(), static_map->getYMin()}}};
  j["obstacles"] = nlohmann::json::array();
  for (const auto& o : obstacles)
    j["obstacles"].push_back(
        {{"id", o.id},
         {"class", o.cls},
         {"stamp_s", o.stamp.Seconds()},
         {"xyz_m", {o.x_m, o.y_m, o.z_m}},
         {"radius_m", o.radius_m},
         {"score", o.score},
         {"range_m", o.range_m},
         {"covariance_xy", {o.covariance_xy(0, 0), o.covariance_xy(0, 1), o.covariance_xy(1, 1)}}});
  j["tracks"] = nlohmann::json::array();
  for (const auto& t : tracks) {
    nlohmann::json track = {{"id", t.id},
                            {"class", t.cls},
                            {"stamp_s", t.stamp.Seconds()},
                            {"xy_m", {t.x_m, t.y_m}},
                            {"v_mps", {t.vx_mps, t.vy_mps}},
                            {"state", t.state},
                            {"motion_model", t.motion_model},
                            {"history_points", t.history.size()}};
    track["prediction"] = nlohmann::json::array();
    for (const auto& p : t.prediction)
      track["prediction"].push_back({{"dt_s", p.dt_s},
                                     {"xy_m", {p.x_m, p.y_m}},
                                     {"covariance_xy", {p.covariance(0, 0), p.covariance(0, 1), p.covariance(1, 1)}}});
    if (!t.class_probabilities.empty()) track["class_probabilities"] = t.class_probabilities;
    j["tracks"].push_back(track);
  }
  if (octree) j["octree"] = {{"resolution_m", octree->getResolution()}, {"leaves", octree->getNumLeafNodes()}};
  if (cost) {
    j["cost"] = {{"cells", {cost->cost.cols, cost->cost.rows}},
                 {"resolution_m", cost->resolution_m},
                 {"lethal", cv::countNonZero(cost->cost == CostGrid::kLethal)},
                 {"inscribed", cv::countNonZero(cost->cost == CostGrid::kInscribed)}};
  }
  return j;
}

WorldModel::WorldModel(const WorldModelOptions& options) : options_(options) {
  const auto problems = options.Relations();
  if (!problems.empty()) throw InputError("world: " + problems.front());
  for (const auto& [cls, margin] : Margins(options.class_margins, nullptr)) margins_[cls] = margin;
  other_margin_ = options.MarginFor("other");
  auto empty = std::make_shared<Snapshot>();
  empty->cost = BuildCost(*empty);
  std::atomic_store(&current_, std::shared_ptr<const Snapshot>(std::move(empty)));
}

std::shared_ptr<const Snapshot> WorldModel::snapshot() const { return std::atomic_load(&current_); }

template <class Edit>
void WorldModel::Publish(Stamp now, Edit&& edit) {
  std::lock_guard<std::mutex> lock(writer_);
  auto next = std::make_shared<Snapshot>(*std::atomic_load(&current_));
  ++next->version;
  if (now > next->stamp) next->stamp = now;
  edit(*next);
  // Expired obstacles leave at every write.
  const Stamp stamp = next->stamp;
  const double lifetime = options_.obstacle_lifetime_s;
  next->obstacles.erase(std::remove_if(next->obstacles.begin(), next->obstacles.end(),
                                       [&](const Obstacle& o) { return SecondsBetween(o.stamp, stamp) > lifetime; }),
                        next->obstacles.end());
  next->cost = BuildCost(*next);
  std::atomic_store(&current_, std::shared_ptr<const Snapshot>(std::move(next)));
}

void WorldModel::SetStaticMap(const mrpt::maps::COccupancyGridMap2D& grid, Stamp stamp) {
  WorldUpdate u;
  u.stamp = stamp;
  u.static_map = std::make_shared<const mrpt::maps::COccupancyGridMap2D>(grid);
  Apply(u);
}

void WorldModel::AddObstacles(const std::vector<Obstacle>& obstacles, Stamp now) {
  WorldUpdate u;
  u.stamp = now;
  u.obstacles = obstacles;
  Apply(u);
}

void WorldModel::SetTracks(const std::vector<Track>& tracks, Stamp now) {
  WorldUpdate u;
  u.stamp = now;
  u.tracks = tracks;
  Apply(u);
}

void WorldModel::SetOctree(std::shared_ptr<const octomap::OcTree> octree, Stamp now) {
  WorldUpdate u;
  u.stamp = now;
  u.octree = std::move(octree);
  Apply(u);
}

void WorldModel::Apply(const WorldUpdate& u) {
  // The static layer is inflated before the lock: writers of other layers need not wait.
  std::shared_ptr<const StaticLayer> layer;
  if (u.static_map) layer = std::make_shared<const StaticLayer>(InflateStatic(*u.static_map));
  Publish(u.stamp, [&](Snapshot& s) {
    if (u.static_map) {
      s.static_map = u.static_map;
      s.static_stamp = u.stamp;
      static_layer_ = layer;  // under the writer lock, read by BuildCost
    }
    if (u.obstacles) {
      s.obstacles.insert(s.obstacles.end(), u.obstacles->begin(), u.obstacles->end());
      s.obstacles_stamp = u.stamp;
    }
    if (u.tracks) {
      s.tracks = *u.tracks;
      s.tracks_stamp = u.stamp;
    }
    if (u.octree) {
      s.octree = u.octree;
      s.octree_stamp = u.stamp;
    }
  });
}

void WorldModel::Advance(Stamp now) {
  Publish(now, [](Snapshot&) {});
}

// The static layer's inflated costs, and its unknown cells; computed once per static
// map (every later write only stamps obstacles on a copy).
WorldModel::StaticLayer WorldModel::InflateStatic(const mrpt::maps::COccupancyGridMap2D& m) const {
  StaticLayer layer;
  CostGrid& grid = layer.grid;
  grid.origin_x_m = m.getXMin();
  grid.origin_y_m = m.getYMin();
  grid.resolution_m = m.getResolution();
  grid.cost = cv::Mat(static_cast<int>(m.getSizeY()), static_cast<int>(m.getSizeX()), CV_8UC1, cv::Scalar(0));
  layer.unknown = cv::Mat(grid.cost.size(), CV_8UC1, cv::Scalar(0));
  cv::Mat free_space(grid.cost.size(), CV_8UC1, cv::Scalar(255));  // 0 where occupied
  for (int r = 0; r < grid.cost.rows; ++r)
    for (int c = 0; c < grid.cost.cols; ++c) {
      const float p = 1.0f - m.getCell(c, r);  // MRPT stores p(free)
      if (p > options_.occupied_probability)
        free_space.at<uint8_t>(r, c) = 0;
      else if (p >= options_.free_probability)
        layer.unknown.at<uint8_t>(r, c) = 1;
    }
  // Distance (m) of every cell to the nearest occupied cell.
  cv::Mat distance;
  cv::distanceTransform(free_space, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  const double footprint = options_.footprint_radius_m, margin = options_.static_margin_m;
  for (int r = 0; r < grid.cost.rows; ++r)
    for (int c = 0; c < grid.cost.cols; ++c) {
      // distanceTransform measures between cell centres: 0 on occupied cells.
      const double d = distance.at<float>(r, c) * grid.resolution_m;
      uint8_t& cell = grid.cost.at<uint8_t>(r, c);
      if (d <= 0)
        cell = CostGrid::kLethal;
      else if (d <= footprint)
        cell = CostGrid::kInscribed;
      else if (d <= footprint + margin)
        cell = static_cast<uint8_t>(std::max(1.0, 252.0 * std::exp(-options_.cost_decay_per_m * (d - footprint))));
    }
  return layer;
}

std::shared_ptr<const CostGrid> WorldModel::BuildCost(const Snapshot& s) const {
  auto grid = std::make_shared<CostGrid>();
  if (static_layer_) {
    *grid = static_layer_->grid;
    grid->cost = static_layer_->grid.cost.clone();
  } else {
    double cx = 0, cy = 0;
    for (const auto& o : s.obstacles) cx += o.x_m / s.obstacles.size(), cy += o.y_m / s.obstacles.size();
    const int cells = static_cast<int>(std::ceil(options_.default_extent_m / options_.default_resolution_m));
    grid->resolution_m = options_.default_resolution_m;
    grid->origin_x_m = std::floor(cx / grid->resolution_m) * grid->resolution_m - cells / 2 * grid->resolution_m;
    grid->origin_y_m = std::floor(cy / grid->resolution_m) * grid->resolution_m - cells / 2 * grid->resolution_m;
    grid->cost = cv::Mat(cells, cells, CV_8UC1, cv::Scalar(0));
  }
  for (const auto& o : s.obstacles) {
    const auto margin = margins_.find(o.cls);
    StampCircle(grid->cost, *grid, o.x_m, o.y_m, o.radius_m, options_.footprint_radius_m,
                margin != margins_.end() ? margin->second : other_margin_, options_.cost_decay_per_m);
  }
  if (static_layer_) grid->cost.setTo(CostGrid::kUnknown, static_layer_->unknown & (grid->cost < CostGrid::kInscribed));
  return grid;
}

}  // namespace specht::world
