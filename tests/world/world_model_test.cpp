// The world model: decay, the cost layer, immutable snapshots under concurrent
// writers and readers (also run under ThreadSanitizer: the tsan presets).
#include "specht/world/world_model.h"

#include <mrpt/maps/COccupancyGridMap2D.h>

#include <atomic>
#include <thread>

#include "specht/core/error.h"
#include "test_support.h"

namespace specht::world {
namespace {

using types::CostGrid;
using types::Obstacle;
using types::Track;

Stamp At(double s) { return Stamp::FromSeconds(1000 + s); }

Obstacle At(double x, double y, const std::string& cls, double t, long id = 0) {
  Obstacle o;
  o.id = id;
  o.cls = cls;
  o.x_m = x;
  o.y_m = y;
  o.radius_m = 0.3;
  o.stamp = At(t);
  return o;
}

TEST(WorldModelTest, ObstaclesDecayAfterTheirLifetime) {
  WorldModelOptions options;
  options.obstacle_lifetime_s = 0.5;
  WorldModel world(options);
  world.AddObstacles({At(1, 1, "car", 0.0, 1)}, At(0.0));
  world.AddObstacles({At(3, 1, "pedestrian", 0.4, 2)}, At(0.4));
  EXPECT_EQ(world.snapshot()->obstacles.size(), 2u);
  world.Advance(At(0.6));  // the first is 0.6 s old
  ASSERT_EQ(world.snapshot()->obstacles.size(), 1u);
  EXPECT_EQ(world.snapshot()->obstacles[0].id, 2);
  world.Advance(At(0.95));
  EXPECT_TRUE(world.snapshot()->obstacles.empty());
  // ... and leave no cost behind.
  EXPECT_EQ(cv::countNonZero(world.snapshot()->cost->cost), 0);
}

// Every cell within footprint + class margin of an obstacle carries cost, lethal and
// inscribed where the formula says, and nothing beyond.
TEST(WorldModelTest, CostLayerMarksEveryCellWithinTheInflationRadius) {
  WorldModelOptions options;
  WorldModel world(options);
  const Obstacle ped = At(2.0, -1.0, "pedestrian", 0.0);
  world.AddObstacles({ped}, At(0.0));
  const auto s = world.snapshot();
  const CostGrid& g = *s->cost;
  const double core = ped.radius_m, inscribed = core + options.footprint_radius_m;
  const double reach = inscribed + options.MarginFor("pedestrian");
  long checked = 0;
  for (int r = 0; r < g.cost.rows; ++r)
    for (int c = 0; c < g.cost.cols; ++c) {
      const cv::Point2d p = g.Centre(c, r);
      const double d = std::hypot(p.x - ped.x_m, p.y - ped.y_m);
      const uint8_t v = g.cost.at<uint8_t>(r, c);
      if (d <= core)
        EXPECT_EQ(v, CostGrid::kLethal);
      else if (d <= inscribed)
        EXPECT_EQ(v, CostGrid::kInscribed);
      else if (d <= reach)
        EXPECT_TRUE(v >= 1 && v < CostGrid::kInscribed) << d;
      else
        EXPECT_EQ(v, CostGrid::kFree);
      checked += d <= reach;
    }
  EXPECT_GT(checked, 500);
  EXPECT_GT(options.MarginFor("pedestrian"), options.MarginFor("car"));
}

TEST(WorldModelTest, StaticMapIsInflatedByTheFootprint) {
  mrpt::maps::COccupancyGridMap2D grid(-5, 5, -5, 5, 0.1);
  // MRPT's cells hold the probability of being free, as every map MRPT builds or loads.
  grid.fill(0.9f);                                                                            // free
  for (float y = -5; y < 5; y += 0.05f) grid.setCell(grid.x2idx(0.0), grid.y2idx(y), 0.05f);  // a wall at x = 0
  grid.setCell(grid.x2idx(4.0), grid.y2idx(4.0), 0.5f);                                       // one unknown cell
  WorldModelOptions options;
  WorldModel world(options);
  world.SetStaticMap(grid, At(0));
  const CostGrid& g = *world.snapshot()->cost;
  EXPECT_EQ(g.cost.cols, static_cast<int>(grid.getSizeX()));
  for (double x : {0.0, 0.3, -0.3, 0.65, 2.0}) {
    int c, r;
    ASSERT_TRUE(g.Cell(x, 1.0, c, r));
    const double d = std::abs(g.Centre(c, r).x - g.Centre(grid.x2idx(0.0), r).x);
    const uint8_t v = g.cost.at<uint8_t>(r, c);
    if (d == 0) {
      EXPECT_EQ(v, CostGrid::kLethal) << x;
    } else if (d <= options.footprint_radius_m) {
      EXPECT_EQ(v, CostGrid::kInscribed) << x;
    } else if (d > options.footprint_radius_m + options.static_margin_m) {
      EXPECT_EQ(v, CostGrid::kFree) << x;
    }
  }
  int c, r;
  g.Cell(4.0, 4.0, c, r);
  EXPECT_EQ(g.cost.at<uint8_t>(r, c), CostGrid::kUnknown);
  EXPECT_EQ(world.snapshot()->ToJson()["cost"]["cells"][0], grid.getSizeX());
  // Later writes keep the static layer (computed once per static map).
  world.AddObstacles({At(3.0, -3.0, "car", 0.1)}, At(0.1));
  const CostGrid& after = *world.snapshot()->cost;
  EXPECT_EQ(after.cost.at<uint8_t>(r, c), CostGrid::kUnknown);
  int wall_c, wall_r;
  ASSERT_TRUE(after.Cell(0.0, 1.0, wall_c, wall_r));
  EXPECT_EQ(after.cost.at<uint8_t>(wall_r, wall_c), CostGrid::kLethal);
  ASSERT_TRUE(after.Cell(3.0, -3.0, wall_c, wall_r));
  EXPECT_EQ(after.cost.at<uint8_t>(wall_r, wall_c), CostGrid::kLethal);
}

// Writers keep an invariant in every update (obstacle ids are 0..n−1 of one batch
// size each, the cost layer built from exactly those obstacles); readers check it in
// every snapshot they take. A torn snapshot would break it.
TEST(WorldModelTest, ConcurrentWritersAndReadersNeverSeeATornSnapshot) {
  WorldModelOptions options;
  options.obstacle_lifetime_s = 1e3;
  options.default_extent_m = 20;
  options.default_resolution_m = 0.25;
  WorldModel world(options);
  std::atomic<bool> stop{false};
  std::atomic<long> snapshots{0}, problems{0};
  auto writer = [&](int who) {
    for (int i = 0; i < 60; ++i) {
      std::vector<Obstacle> batch;
      for (int k = 0; k < 3; ++k) batch.push_back(At(who * 2.0 + k, i * 0.1 - 3, "car", 0, who * 1000 + i * 3 + k));
      world.AddObstacles(batch, At(0.001 * i));
    }
  };
  auto reader = [&] {
    uint64_t last = 0;
    while (!stop) {
      const auto s = world.snapshot();
      ++snapshots;
      if (s->obstacles.size() % 3 != 0) ++problems;
      if (s->version < last) ++problems;
      last = s->version;
      for (size_t i = 0; i < s->obstacles.size(); i += 3)
        if (s->obstacles[i + 2].id != s->obstacles[i].id + 2) ++problems;  // batches stay whole
      for (const auto& o : s->obstacles) {
        int c, r;
        if (s->cost->Cell(o.x_m, o.y_m, c, r) && s->cost->cost.at<uint8_t>(r, c) != CostGrid::kLethal) ++problems;
      }
    }
  };
  std::thread r1(reader), r2(reader);
  std::thread w1(writer, 0), w2(writer, 1);
  w1.join();
  w2.join();
  stop = true;
  r1.join();
  r2.join();
  EXPECT_EQ(problems.load(), 0);
  EXPECT_GT(snapshots.load(), 10);
  EXPECT_EQ(world.snapshot()->obstacles.size(), 360u);
  EXPECT_EQ(world.snapshot()->version, 120u);
}

// A perception cycle writes obstacles, tracks, the OctoMap and (now and then) the
// static map in one update; readers on other threads check that every snapshot's
// per-frame layers are of one stamp and that the static layer is not newer.
TEST(WorldModelTest, OneUpdatesLayersAreSeenTogetherOrNotAtAll) {
  WorldModelOptions options;
  options.obstacle_lifetime_s = 1e3;
  WorldModel world(options);
  mrpt::maps::COccupancyGridMap2D grid(-5, 5, -5, 5, 0.1);
  std::atomic<bool> stop{false};
  std::atomic<long> snapshots{0}, problems{0};
  auto writer = [&] {
    for (int i = 1; i <= 80; ++i) {
      WorldUpdate u;
      u.stamp = At(0.1 * i);
      u.obstacles = std::vector<Obstacle>{At(1, 0, "car", 0.1 * i, i)};
      Track t;
      t.id = i;
      t.stamp = u.stamp;
      u.tracks = std::vector<Track>{t};
      auto tree = std::make_shared<octomap::OcTree>(0.5);
      tree->updateNode(octomap::point3d(0.1f * i, 0, 0), true);
      u.octree = tree;
      if (i % 10 == 0) u.static_map = std::make_shared<const mrpt::maps::COccupancyGridMap2D>(grid);
      world.Apply(u);
    }
  };
  auto reader = [&] {
    while (!stop) {
      const auto s = world.snapshot();
      ++snapshots;
      if (!s->octree) continue;  // before the first update
      const bool same = s->obstacles_stamp == s->stamp && s->tracks_stamp == s->stamp && s->octree_stamp == s->stamp;
      const bool of_it = s->obstacles.back().stamp == s->stamp && s->tracks.size() == 1 &&
                         s->tracks[0].stamp == s->stamp && s->octree->getNumLeafNodes() == 1;
      if (!same || !of_it || s->static_stamp > s->stamp || (s->static_map && s->static_stamp.ns == 0)) ++problems;
    }
  };
  std::thread r1(reader), r2(reader), w(writer);
  w.join();
  stop = true;
  r1.join();
  r2.join();
  EXPECT_EQ(problems.load(), 0);
  EXPECT_GT(snapshots.load(), 10);
  const auto last = world.snapshot();
  EXPECT_EQ(last->version, 80u);
  EXPECT_EQ(last->static_stamp, At(8.0));
  EXPECT_EQ(last->obstacles.size(), 80u);
}

TEST(WorldModelTest, BadMarginsAreRejected) {
  WorldModelOptions options;
  options.class_margins = {"car=-1"};
  EXPECT_THROW(WorldModel{options}, InputError);
  options.class_margins = {"car"};
  EXPECT_THROW(WorldModel{options}, InputError);
}

}  // namespace
}  // namespace specht::world
