// The simulator: sensors agree with the world's ground truth, agent classes move
// differently, runs are reproducible, and bad scenario files are named precisely.
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "specht/core/error.h"
#include "specht/sim/simulator.h"
#include "test_support.h"

namespace specht::sim {
namespace {

using ::testing::HasSubstr;

std::string ScenarioPath(const std::string& name) {
  return testing::SourceDir() + "/datasets/scenarios/" + name + ".yaml";
}

// Acceptance: every noiseless beam endpoint lies within one cell of an occupied cell
// of the true grid.
TEST(SimulatorTest, NoiselessBeamEndpointsLieOnTheTrueGrid) {
  for (const char* name : {"course-loop", "urban-crossing", "parking-lot"}) {
    Scenario s = LoadScenario(ScenarioPath(name));
    s.agents.clear();  // the true grid is the static world
    s.lidar.range_noise_m = 0;
    s.lidar.dropout = 0;
    Simulator sim(s, 7);
    const double res = 0.05;
    const auto grid = sim.world().TrueGrid(res);
    // Distance (in cells) from every cell to the nearest occupied one.
    cv::Mat free(grid.getSizeY(), grid.getSizeX(), CV_8U);
    for (unsigned y = 0; y < grid.getSizeY(); ++y) {
      for (unsigned x = 0; x < grid.getSizeX(); ++x) free.at<uint8_t>(y, x) = grid.getCell(x, y) < 0.5f ? 0 : 255;
    }
    cv::Mat dist;
    cv::distanceTransform(free, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE);
    long endpoints = 0, off = 0;
    for (int step = 0; step < 300; ++step) {
      sim.Step([&](Stamp, const mrpt::obs::CObservation::Ptr& obs) {
        auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs);
        if (!scan) return;
        const Pose2 ego = sim.ego().pose;
        const double c = std::cos(ego.yaw_rad), sn = std::sin(ego.yaw_rad);
        const double sx = ego.x + c * s.lidar.mount.x - sn * s.lidar.mount.y;
        const double sy = ego.y + sn * s.lidar.mount.x + c * s.lidar.mount.y;
        for (size_t i = 0; i < scan->getScanSize(); ++i) {
          if (!scan->getScanRangeValidity(i)) continue;
          const double a = ego.yaw_rad + s.lidar.mount.yaw_rad - s.lidar.fov_rad / 2 +
                           s.lidar.fov_rad * i / (scan->getScanSize() - 1);
          const double r = scan->getScanRange(i);
          const int cx = grid.x2idx(sx + r * std::cos(a)), cy = grid.y2idx(sy + r * std::sin(a));
          ++endpoints;
          if (dist.at<float>(cy, cx) > 1.0f) ++off;
        }
      });
    }
    EXPECT_GT(endpoints, 5000) << name;
    EXPECT_EQ(off, 0) << name << ": " << off << " of " << endpoints << " endpoints off the true grid";
  }
}

struct ClassSamples {
  std::vector<double> speed, turn;
};

std::map<AgentClass, ClassSamples> AgentSamples(const std::string& scenario, std::initializer_list<uint64_t> seeds) {
  std::map<AgentClass, ClassSamples> out;
  const Scenario s = LoadScenario(ScenarioPath(scenario));
  for (uint64_t seed : seeds) {
    Simulator sim(s, seed);
    for (int step = 1; step <= static_cast<int>(s.duration_s / Simulator::kStepS); ++step) {
      sim.Step([](Stamp, const mrpt::obs::CObservation::Ptr&) {});
      if (step % 10 != 0) continue;
      for (const auto& a : sim.agents()) {
        out[a.cls].speed.push_back(a.speed_mps);
        out[a.cls].turn.push_back(std::abs(a.yaw_rate));
      }
    }
  }
  return out;
}

// The best accuracy any single speed threshold reaches telling class a from class b.
double BestThresholdAccuracy(const std::vector<double>& a, const std::vector<double>& b) {
  double best = 0;
  for (double t = 0; t < 15; t += 0.05) {
    long right = 0;
    for (double v : a) right += v < t;
    for (double v : b) right += v >= t;
    best = std::max(best, static_cast<double>(right) / (a.size() + b.size()));
  }
  return best;
}

double Median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// Acceptance: motion differs by class in measurable ways, but no single speed
// threshold separates the classes.
TEST(SimulatorTest, AgentClassesMoveDifferentlyButSpeedAloneDoesNotSeparateThem) {
  auto samples = AgentSamples("urban-crossing", {1, 2, 3});
  const auto& ped = samples[AgentClass::kPedestrian];
  const auto& cyc = samples[AgentClass::kCyclist];
  const auto& car = samples[AgentClass::kCar];
  ASSERT_GT(ped.speed.size(), 1000u);
  ASSERT_GT(cyc.speed.size(), 500u);
  ASSERT_GT(car.speed.size(), 500u);
  const double ped_cyc = BestThresholdAccuracy(ped.speed, cyc.speed);
  const double cyc_car = BestThresholdAccuracy(cyc.speed, car.speed);
  const double ped_car = BestThresholdAccuracy(ped.speed, car.speed);
  std::printf(
      "speed medians: pedestrian %.2f, cyclist %.2f, car %.2f m/s; best single-threshold accuracy "
      "ped/cyc %.3f, cyc/car %.3f, ped/car %.3f\n",
      Median(ped.speed), Median(cyc.speed), Median(car.speed), ped_cyc, cyc_car, ped_car);
  std::printf("|turn rate| p50: pedestrian %.3f, cyclist %.3f, car %.3f rad/s\n", Median(ped.turn), Median(cyc.turn),
              Median(car.turn));
  EXPECT_LT(Median(ped.speed), Median(cyc.speed));
  EXPECT_LT(Median(cyc.speed), Median(car.speed));
  EXPECT_LT(ped_cyc, 0.95);
  EXPECT_LT(cyc_car, 0.95);
  EXPECT_LT(ped_car, 0.98);
  // Pedestrians wander (heading noise, sharp turns); cyclists and cars hold lines.
  EXPECT_GT(Median(ped.turn), 2 * Median(cyc.turn));
  // Cars stop at stop waypoints; pedestrians pause; cyclists roll on.
  auto stopped = [](const std::vector<double>& v) {
    return std::count_if(v.begin(), v.end(), [](double s) { return s < 0.05; }) / static_cast<double>(v.size());
  };
  EXPECT_GT(stopped(car.speed), 0.02);
  EXPECT_GT(stopped(ped.speed), 0.05);
  EXPECT_LT(stopped(cyc.speed), 0.01);
}

std::string ErrorOf(const std::string& yaml) {
  try {
    ParseScenario(yaml, "bad.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A commanded ego at constant speed and steering drives a circle: its rear axle
// (rear_overhang_m from the rear bumper) on radius R = L / tan δ, its box centre
// (the reported pose, a = length/2 − rear_overhang ahead) on √(R² + a²).
TEST(SimulatorTest, CommandedEgoTurnsAboutItsRearAxle) {
  Scenario s = LoadScenario(ScenarioPath("course-loop"));
  ASSERT_NEAR(s.ego.model.rear_overhang_m, 0.5, 1e-12);
  s.agents.clear();
  Simulator sim(s, 1);
  const double steer = 0.3, radius = s.ego.model.wheelbase_m / std::tan(steer), ahead = s.ego.model.PivotAhead();
  sim.CommandEgo({1.0, steer, 10.0});
  const auto ignore = [](Stamp, const mrpt::obs::CObservation::Ptr&) {};
  for (int i = 0; i < 200; ++i) sim.Step(ignore);  // reach the speed and steering
  std::vector<std::pair<double, double>> rear, centre;
  for (int i = 0; i < 400; ++i) {
    sim.Step(ignore);
    const Pose2& p = sim.ego().pose;
    centre.push_back({p.x, p.y});
    rear.push_back({p.x - ahead * std::cos(p.yaw_rad), p.y - ahead * std::sin(p.yaw_rad)});
  }
  // The circle's centre: left of the rear axle by R.
  const Pose2& p = sim.ego().pose;
  const double cx = rear.back().first - radius * std::sin(p.yaw_rad),
               cy = rear.back().second + radius * std::cos(p.yaw_rad);
  for (size_t i = 0; i < rear.size(); i += 20) {
    EXPECT_NEAR(std::hypot(rear[i].first - cx, rear[i].second - cy), radius, 0.02) << i;
    EXPECT_NEAR(std::hypot(centre[i].first - cx, centre[i].second - cy), std::hypot(radius, ahead), 0.02) << i;
  }
}

// The world steps every 10 ms: a rate that divides 100 Hz samples on a fixed step,
// another keeps its average rate (40 Hz: 3, 2, 3, 2 … steps apart, never 33.3 Hz).
TEST(SimulatorTest, SensorsKeepTheirRateWhereItDoesNotDivideTheStep) {
  Scenario s = LoadScenario(ScenarioPath("course-loop"));
  s.agents.clear();
  s.lidar.rate_hz = 40, s.odometry.rate_hz = 30, s.imu.rate_hz = 100;
  Simulator sim(s, 1);
  std::map<std::string, std::vector<int64_t>> stamps;
  for (int i = 0; i < 1000; ++i)  // 10 s
    sim.Step([&](Stamp t, const mrpt::obs::CObservation::Ptr& o) {
      stamps[o->GetRuntimeClass()->className].push_back(t.ns);
    });
  const auto& scans = stamps["mrpt::obs::CObservation2DRangeScan"];
  EXPECT_EQ(scans.size(), 400u);
  EXPECT_EQ(stamps["mrpt::obs::CObservationOdometry"].size(), 300u);
  EXPECT_EQ(stamps["mrpt::obs::CObservationIMU"].size(), 1000u);
  for (size_t i = 1; i < scans.size(); ++i) {
    const int64_t gap_ms = (scans[i] - scans[i - 1]) / 1000000;
    EXPECT_TRUE(gap_ms == 20 || gap_ms == 30) << i << ": " << gap_ms << " ms";
  }
}

TEST(ScenarioTest, BadFilesNameFileLineKeyAndReason) {
  EXPECT_EQ(ErrorOf("name: x\nduraton_s: 10\n"), "bad.yaml:2: duraton_s: unknown key (did you mean 'duration_s'?)");
  EXPECT_EQ(ErrorOf("world:\n  objects:\n    - {type: wall, polygon: [[0, 0], [4, 4], [4, 0], [0, 4]]}\n"),
            "bad.yaml:3: world.objects[0].polygon: self-intersecting");
  EXPECT_EQ(
      ErrorOf("world:\n  bounds: [0, 0, 10, 10]\nagents:\n  - {id: 1, class: cyclist, route: [[1, 1], [12, 1]]}\n"),
      "bad.yaml:4: agents[0].route[1]: agent outside the world bounds");
  EXPECT_EQ(ErrorOf("ego:\n  cruise_speed_mps: -2\n"), "bad.yaml:2: ego.cruise_speed_mps: value -2 is outside [0, 60]");
  EXPECT_EQ(ErrorOf("agents:\n  - {id: 1, class: horse, route: [[1, 1], [2, 2]]}\n"),
            "bad.yaml:2: agents[0].class: 'horse' is not one of: car, cyclist, pedestrian");
  EXPECT_EQ(ErrorOf("world:\n  bounds: [0, 0, 20, 20]\n  objects:\n    - {type: building, polygon: [[5, 5], [8, 5], "
                    "[8, 8], [5, 8]]}\n"
                    "agents:\n  - {id: 1, class: pedestrian, route: [[1, 6], [12, 6]]}\n"),
            "bad.yaml:6: agents[0].route: leg 0 -> 1 passes through world.objects[0]");
  EXPECT_THAT(ErrorOf("name: [unclosed\n"), HasSubstr("bad.yaml:"));
  EXPECT_THROW(LoadScenario("/nonexistent.yaml"), InputError);
  // Found by fuzz_scenario: lists of numbers holding something else.
  EXPECT_EQ(ErrorOf("sensors:\n  stereo:\n    mount: [0, 0, 1, x, 0]\n"),
            "bad.yaml:3: sensors.stereo.mount: expected [x_m, y_m, z_m, yaw_deg, pitch_deg]: 5 numbers");
  EXPECT_EQ(ErrorOf("world:\n  bounds: [0, 0, [1], 10]\n"),
            "bad.yaml:2: world.bounds: expected [xmin, ymin, xmax, ymax]: 4 numbers");
  EXPECT_EQ(ErrorOf("world:\n  parking_bays:\n    - {name: A, pose: [1, 1, 0], size_m: [5, .nan]}\n"),
            "bad.yaml:3: world.parking_bays[0].size_m: numbers must be finite");
  EXPECT_EQ(ErrorOf("world:\n  parking_bays: {0: x}\n"), "bad.yaml:2: world.parking_bays: expected a list of bays");
  EXPECT_THAT(ErrorOf("agents:\n  - {id: 1, class: car, route: [{stop: true}, [2, 2]]}\n"),
              ::testing::StartsWith("bad.yaml: agents[0].route[0].at: expected [x, y]\n"));
}

TEST(ScenarioTest, ShippedScenariosLoad) {
  for (const char* name : {"course-loop", "urban-crossing", "parking-lot"}) {
    const Scenario s = LoadScenario(ScenarioPath(name));
    EXPECT_FALSE(s.objects.empty()) << name;
    EXPECT_FALSE(s.agents.empty()) << name;
    EXPECT_FALSE(s.bays.empty()) << name;
  }
}

}  // namespace
}  // namespace specht::sim

#include <opencv2/calib3d.hpp>

namespace specht::sim {
namespace {

// Renders the urban crossing's camera view after `seconds` (that frame only).
StereoFrame RenderAt(double seconds, uint64_t seed) {
  static Scenario s;
  s = LoadScenario(ScenarioPath("urban-crossing"));
  s.stereo->rate_hz = 1.0 / seconds;
  Simulator sim(s, seed);
  StereoFrame last;
  for (int k = 0; k < static_cast<int>(seconds / Simulator::kStepS); ++k) {
    sim.Step([](Stamp, const mrpt::obs::CObservation::Ptr&) {}, [&](Stamp, const StereoFrame& f) { last = f; });
  }
  return last;
}

// Acceptance: OpenCV SGBM on a rendered pair has D1-all ≤ 10 % against the rendered
// true disparity, on the pixels that see a surface (not the sky).
TEST(StereoRenderTest, OpenCvSgbmAgreesWithTheRenderedTruth) {
  for (double t : {3.0, 7.0}) {
    const StereoFrame f = RenderAt(t, 2);
    ASSERT_FALSE(f.left.empty());
    auto sgbm = cv::StereoSGBM::create(0, 64, 5, 8 * 25, 32 * 25, 1, 0, 10, 100, 32, cv::StereoSGBM::MODE_SGBM_3WAY);
    cv::Mat raw, disparity;
    sgbm->compute(f.left, f.right, raw);
    raw.convertTo(disparity, CV_32F, 1.0 / 16.0);
    long pixels = 0, bad = 0;
    for (int v = 0; v < disparity.rows; ++v) {
      for (int u = 64; u < disparity.cols; ++u) {  // SGBM has no estimate left of its range
        const float truth = f.disparity.at<float>(v, u);
        if (truth <= 0 || truth > 63) continue;
        ++pixels;
        const float d = disparity.at<float>(v, u), err = std::abs(d - truth);
        bad += d < 0 || (err > 3 && err > 0.05f * truth);
      }
    }
    const double d1 = static_cast<double>(bad) / pixels;
    std::printf("t=%.0f s: SGBM D1-all %.2f %% over %ld pixels with truth\n", t, 100 * d1, pixels);
    EXPECT_GT(pixels, f.left.total() / 3);
    EXPECT_LE(d1, 0.10);
  }
}

// Acceptance: warping the right image by the true disparity reproduces the left image
// on pixels the right camera also sees.
TEST(StereoRenderTest, RightImageWarpedByTrueDisparityReproducesTheLeft) {
  const StereoFrame f = RenderAt(5.0, 2);
  double sum = 0;
  long pixels = 0;
  for (int v = 0; v < f.left.rows; ++v) {
    for (int u = 0; u < f.left.cols; ++u) {
      const float d = f.disparity.at<float>(v, u), z = f.depth.at<float>(v, u);
      const float ur = static_cast<float>(u) - d;
      if (d <= 0 || ur < 0 || ur > f.left.cols - 2) continue;
      const int u0 = static_cast<int>(ur);
      const float w = ur - u0;
      // Not occluded: the right camera sees the same depth there.
      const float zr = (1 - w) * f.depth_right.at<float>(v, u0) + w * f.depth_right.at<float>(v, u0 + 1);
      if (std::abs(zr - z) > 0.02f * z) continue;
      const float right = (1 - w) * f.right.at<uint8_t>(v, u0) + w * f.right.at<uint8_t>(v, u0 + 1);
      sum += std::abs(right - f.left.at<uint8_t>(v, u));
      ++pixels;
    }
  }
  const double mean_error = sum / pixels;
  std::printf("warp: mean |left - warped right| %.2f grey levels over %ld pixels\n", mean_error, pixels);
  EXPECT_GT(pixels, f.left.total() / 3);
  EXPECT_LT(mean_error, 4.0);
}

TEST(StereoRenderTest, LabelsListTheAgentsInView) {
  // Within 12 s the crossing's agents come into view of the camera.
  const Scenario s = LoadScenario(ScenarioPath("urban-crossing"));
  Simulator sim(s, 2);
  long labels = 0;
  for (int k = 0; k < 1200 && labels == 0; ++k) {
    sim.Step([](Stamp, const mrpt::obs::CObservation::Ptr&) {},
             [&](Stamp, const StereoFrame& f) {
               for (const auto& line : f.kitti_labels) {
                 ++labels;
                 std::istringstream fields(line);
                 std::string type;
                 double truncated, occluded, alpha, l, t, r, b;
                 fields >> type >> truncated >> occluded >> alpha >> l >> t >> r >> b;
                 EXPECT_TRUE(type == "Pedestrian" || type == "Cyclist" || type == "Car") << line;
                 EXPECT_LE(l, r);
                 EXPECT_LE(t, b);
               }
             });
  }
  EXPECT_GT(labels, 0);
}

// The rasteriser's depth against an independent ray cast (ground plane and every
// vertical face, nearest hit) at every 7th pixel of a frame of the static world:
// where both hit the same surface the depths agree to 1e-4 relative, and the ray cast
// finds nothing the rasteriser left as sky.
TEST(StereoRenderTest, RasterisedDepthAgreesWithARayCast) {
  Scenario s = LoadScenario(ScenarioPath("urban-crossing"));
  const World world(s);
  const StereoRenderer renderer(s, world, *s.stereo);
  const Pose2 ego{12.0, 3.0, 0.3};
  const StereoFrame f = renderer.Render(ego, {});
  const StereoSpec& c = *s.stereo;
  const double cs = std::cos(ego.yaw_rad), sn = std::sin(ego.yaw_rad);
  const cv::Vec3d o(ego.x + cs * c.x_m - sn * c.y_m, ego.y + sn * c.x_m + cs * c.y_m, c.z_m);
  const double yaw = ego.yaw_rad + c.yaw_rad, cp = std::cos(c.pitch_rad), sp = std::sin(c.pitch_rad);
  const cv::Vec3d forward(std::cos(yaw) * cp, std::sin(yaw) * cp, -sp), right(std::sin(yaw), -std::cos(yaw), 0);
  const cv::Vec3d down = forward.cross(right);
  long compared = 0, disagree = 0;
  for (int v = 0; v < c.height; v += 7) {
    for (int u = 0; u < c.width; u += 7) {
      const double x = (u - (c.width - 1) / 2.0) / c.focal_px, y = (v - (c.height - 1) / 2.0) / c.focal_px;
      const cv::Vec3d d = right * x + down * y + forward;  // camera z = 1: t is the depth
      double best = d[2] < 0 ? -o[2] / d[2] : INFINITY;
      for (const auto& obj : s.objects) {
        const size_t n = obj.polygon.size(), edges = obj.closed ? n : n - 1;
        for (size_t i = 0; i < edges; ++i) {
          const Vec2 a = obj.polygon[i], b = obj.polygon[(i + 1) % n];
          const double ex = b.x - a.x, ey = b.y - a.y, den = d[0] * ey - d[1] * ex;
          if (std::abs(den) < 1e-12) continue;
          const double t = ((a.x - o[0]) * ey - (a.y - o[1]) * ex) / den;
          const double w = ((a.x - o[0]) * d[1] - (a.y - o[1]) * d[0]) / den, z = o[2] + t * d[2];
          if (t > 0.05 && w >= 0 && w <= 1 && z >= 0 && z <= obj.height_m) best = std::min(best, t);
        }
      }
      const float rendered = f.depth.at<float>(v, u);
      if (!std::isfinite(best)) {
        EXPECT_EQ(rendered, 0.0f) << u << "," << v;
        continue;
      }
      ++compared;
      if (std::abs(rendered - best) > 1e-4 * best) ++disagree;
      if (rendered > 0) {
        EXPECT_NEAR(f.disparity.at<float>(v, u), c.focal_px * c.baseline_m / rendered, 1e-3);
      }
    }
  }
  EXPECT_GT(compared, 5000);
  // Only pixels on a face's very edge may disagree (the edge test in float).
  EXPECT_LT(static_cast<double>(disagree) / compared, 0.002) << disagree << " of " << compared;
}

// Sprites from the shipped photographs: every class has tuning and held-out ones,
// each a tight cut-out with a mask; a named one is found, an unknown name is refused
// with the names listed, a missing source directory is named.
TEST(SpriteTest, TheLibraryCutsOutEveryClassAndHoldsSomeOut) {
  const std::string data = testing::DataDir();
  SPECHT_REQUIRE_FILE(data.empty() || !std::filesystem::exists(data + "/sprites") ? std::string() : data);
  const SpriteLibrary lib = SpriteLibrary::Load(data + "/sprites");
  for (const char* cls : {"pedestrian", "cyclist", "car"}) {
    EXPECT_FALSE(lib.Of(cls, SpriteSet::kTuning).empty()) << cls;
    EXPECT_FALSE(lib.Of(cls, SpriteSet::kHeldOut).empty()) << cls;
    for (const Sprite* sp : lib.Of(cls, SpriteSet::kAll)) {
      ASSERT_EQ(sp->bgr.size(), sp->alpha.size());
      EXPECT_GE(sp->bgr.rows, 80);
      // Tight: the mask reaches every side of the cut-out.
      const cv::Rect tight = cv::boundingRect(sp->alpha);
      EXPECT_EQ(tight, cv::Rect(0, 0, sp->alpha.cols, sp->alpha.rows)) << sp->name;
    }
  }
  const auto held_out = lib.Of("car", SpriteSet::kHeldOut);
  for (const Sprite* sp : held_out)
    EXPECT_EQ(sp->name.rfind("davis/car-roundabout/", 0) == 0 || sp->name.rfind("coco/", 0) == 0, true);
  EXPECT_EQ(&lib.Named(held_out.front()->name), held_out.front());
  EXPECT_THROW(lib.Named("coco/0/0"), InputError);
  try {
    SpriteLibrary::Load(testing::TempDir() + "/nothing");
    ADD_FAILURE() << "loaded sprites from an empty directory";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("annotations.json"));
  }
}

// With sprites the camera shows each agent as a photograph on its plane: the label's
// box is the sprite's and the depth inside it is the agent's range.
TEST(StereoRenderTest, SpritesStandAtTheirAgentsRange) {
  const std::string data = testing::DataDir();
  SPECHT_REQUIRE_FILE(data.empty() || !std::filesystem::exists(data + "/sprites") ? std::string() : data);
  const SpriteLibrary lib = SpriteLibrary::Load(data + "/sprites");
  Scenario s = LoadScenario(ScenarioPath("urban-crossing"));
  const World world(s);
  const StereoRenderer renderer(s, world, *s.stereo, &lib);
  const Pose2 ego{10.0, 4.0, 0.0};  // on the road south of the first block, looking east
  const StereoFrame f = renderer.Render(ego, {{{20.0, 5.0, M_PI / 2}, 0.5, 0.5, 1.75, 7, "Pedestrian", ""},
                                              {{30.0, 3.5, 0.0}, 4.5, 1.8, 1.5, 8, "Car", ""}});
  ASSERT_EQ(f.agents.size(), 2u);
  for (const AgentView& a : f.agents) {
    EXPECT_FALSE(a.sprite.empty());
    EXPECT_GT(a.visible, 0.95) << a.sprite;
    // Most of the box is the sprite, at the agent's range (its plane faces the camera).
    long at_range = 0;
    for (int v = static_cast<int>(a.box.y); v < a.box.br().y; ++v)
      for (int u = static_cast<int>(a.box.x); u < a.box.br().x; ++u)
        at_range += std::abs(f.depth.at<float>(v, u) - a.range_m) < 0.03 * a.range_m;
    EXPECT_GT(at_range, 0.4 * a.box.area()) << a.sprite;
  }
  // A car seen from behind shows a rear view: narrower than a side view.
  EXPECT_LT(f.agents[1].box.width / f.agents[1].box.height, 2.0) << f.agents[1].sprite;
}

}  // namespace
}  // namespace specht::sim
