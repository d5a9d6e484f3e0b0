// specht/world/world_model.h: the shared map every module meets in.
//
// Layers, all in the map frame:
//   static     the occupancy grid from SLAM (MRPT COccupancyGridMap2D)
//   obstacles  detections placed in 3D by stereo fusion: class, time stamp,
//              covariance; each lives `obstacle_lifetime_s` after its stamp
//   tracks     the multi-object tracker's estimates (position, velocity, class)
//   3D         an OctoMap of stereo points
//   cost       for the planner, on the static grid's cells (ROS costmap_2d values):
//                254 lethal       an occupied static cell or an obstacle's extent
//                253 inscribed    within footprint_radius_m of one (the car's
//                                 centre there means a collision)
//                252 … 1          beyond that, within the class's safety margin:
//                                 252 · exp(−decay · (r − footprint)) (at least 1)
//                0 free, 255 unknown (unknown static cells, nothing nearer)
//
// Concurrency: writers are serialised and publish a new immutable Snapshot (copy on
// write, the cost layer rebuilt); readers take the current snapshot with one atomic
// load and keep it as long as they like. A reader never sees half an update.
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/poses/CPose3D.h>
#include <octomap/OcTree.h>

#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "specht/core/params.h"
#include "specht/core/time.h"
#include "specht/types/cost_grid.h"
#include "specht/types/obstacle.h"
#include "specht/types/track.h"

namespace specht::world {

// Section "world".
struct WorldModelOptions {
  double obstacle_lifetime_s = 1.0;
  double footprint_radius_m = 0.7;
  double static_margin_m = 0.3;
  std::vector<std::string> class_margins = {"pedestrian=1.5", "cyclist=1.2",      "car=0.8",  "truck=1.0",
                                            "bus=1.0",        "traffic_sign=0.2", "other=0.5"};
  double cost_decay_per_m = 3.0;
  double occupied_probability = 0.65;
  double free_probability = 0.35;
  double default_resolution_m = 0.1;  // cost grid without a static map
  double default_extent_m = 60;       // …its size, centred on the first obstacles

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Param("obstacle_lifetime_s", obstacle_lifetime_s, "an obstacle disappears this long after its stamp",
            Range::Of(0.05, 60.0).Log());
    v.Param("footprint_radius_m", footprint_radius_m, "radius of the car's circumscribed footprint",
            Range::Of(0.1, 5.0));
    v.Param("static_margin_m", static_margin_m, "safety margin beyond the footprint around static obstacles",
            Range::Of(0.0, 5.0));
    v.Param("class_margins", class_margins, "safety margin beyond the footprint per class, \"class=metres\"");
    v.Param("cost_decay_per_m", cost_decay_per_m, "how fast the cost falls off inside a margin",
            Range::Of(0.1, 20.0).Log());
    v.Param("occupied_probability", occupied_probability, "a static cell is occupied above this", Range::Of(0.5, 0.99));
    v.Param("free_probability", free_probability, "a static cell is free below this", Range::Of(0.01, 0.5));
    v.Param("default_resolution_m", default_resolution_m, "cost grid cell size without a static map",
            Range::Of(0.02, 1.0));
    v.Param("default_extent_m", default_extent_m, "cost grid size without a static map", Range::Of(5.0, 1000.0));
  }
  std::vector<std::string> Relations() const;
  double MarginFor(const std::string& cls) const;
};

struct Snapshot {
  uint64_t version = 0;
  Stamp stamp;  // the latest time the model was advanced or written to
  // When each layer was last written: the data it holds is of that time.
  Stamp static_stamp, obstacles_stamp, tracks_stamp, octree_stamp;
  std::shared_ptr<const mrpt::maps::COccupancyGridMap2D> static_map;
  std::vector<types::Obstacle> obstacles;
  std::vector<types::Track> tracks;
  std::shared_ptr<const octomap::OcTree> octree;
  std::shared_ptr<const types::CostGrid> cost;

  nlohmann::json ToJson() const;  // layers summarised, obstacles and tracks in full
};

// One perception cycle's layers, written together: a reader sees all of them or none.
// Unset members leave their layer as it is.
struct WorldUpdate {
  Stamp stamp;
  std::optional<std::vector<types::Obstacle>> obstacles;              // added to the obstacle layer
  std::optional<std::vector<types::Track>> tracks;                    // replace the track layer
  std::shared_ptr<const octomap::OcTree> octree;                      // replaces the 3D layer
  std::shared_ptr<const mrpt::maps::COccupancyGridMap2D> static_map;  // replaces the static layer
};

class WorldModel {
 public:
  explicit WorldModel(const WorldModelOptions& options);

  // Writers (serialised; each publishes a new snapshot).
  void SetStaticMap(const mrpt::maps::COccupancyGridMap2D& grid, Stamp stamp);
  void AddObstacles(const std::vector<types::Obstacle>& obstacles, Stamp now);
  void SetTracks(const std::vector<types::Track>& tracks, Stamp now);
  void SetOctree(std::shared_ptr<const octomap::OcTree> octree, Stamp now);
  // Every layer `update` carries, in one snapshot stamped update.stamp.
  void Apply(const WorldUpdate& update);
  // Drops the obstacles older than their lifetime at `now`.
  void Advance(Stamp now);

  // Readers: the current snapshot, immutable.
  std::shared_ptr<const Snapshot> snapshot() const;

 private:
  template <class Edit>
  void Publish(Stamp now, Edit&& edit);
  struct StaticLayer {
    types::CostGrid grid;  // the static map inflated
    cv::Mat unknown;       // CV_8U, 1 on unknown static cells
  };
  StaticLayer InflateStatic(const mrpt::maps::COccupancyGridMap2D& grid) const;
  std::shared_ptr<const types::CostGrid> BuildCost(const Snapshot& s) const;

  WorldModelOptions options_;
  std::map<std::string, double> margins_;  // class_margins, parsed once
  double other_margin_ = 0;
  std::shared_ptr<const StaticLayer> static_layer_;  // written under writer_
  std::mutex writer_;
  std::shared_ptr<const Snapshot> current_;  // read and replaced with std::atomic_load/store
};

}  // namespace specht::world
