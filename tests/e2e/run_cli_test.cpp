// `specht run`: the closed loop on the shipped scenarios — the mission state
// machine plans, waits for agents, corrects and parks; checked against the
// scenario's ground truth (bay pose, agents' boxes, static map).
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "report.h"
#include "test_support.h"

namespace specht {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// `specht run SCENARIO --seeds SEEDS EXTRA` into a fresh folder; its report, after
// checking that every mission parked cleanly: all completed, no collision, within
// the parking tolerance (0.2 m, 5°).
nlohmann::json RunParked(const std::string& scenario, const std::string& seeds, const std::string& out,
                         const std::string& extra = "") {
  const auto r = testing::RunSpecht("run '" + testing::SourceDir() + "/datasets/scenarios/" + scenario + "' --seeds " +
                                    seeds + " -q -o '" + out + "' " + extra);
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  const auto report = Report(out);
  const auto& m = report["metrics"];
  EXPECT_EQ(m["success_rate"].get<double>(), 1.0);
  EXPECT_EQ(m["collisions"].get<int>(), 0);  // scored against the true map
  EXPECT_LE(m["max_park_error_m"].get<double>(), 0.2);
  EXPECT_LE(m["max_park_error_deg"].get<double>(), 5.0);
  return report;
}

TEST(RunCliTest, ParksInTheParkingLotWithoutCollisions) {
  const std::string out = testing::TempDir("run_cli") + "/out";
  const auto report = RunParked("parking-lot.yaml", "1-3", out, "--stack truth");
  const auto& m = report["metrics"];
  if (!m["min_pedestrian_distance_m"].is_null()) {  // braces: EXPECT_GE is an if/else inside
    EXPECT_GE(m["min_pedestrian_distance_m"].get<double>(), m["pedestrian_margin_m"].get<double>());
  }
  for (const auto& run : report["runs"]) {
    EXPECT_EQ(run["states_visited"].back(), "done");
    EXPECT_GT(run["planning_ms"]["count"].get<int>(), 0);
  }
  for (const char* f : {"run-1.png", "steps-1.jsonl", "paths-1.csv", "report.json"})
    EXPECT_TRUE(fs::exists(out + "/" + f)) << f;
}

// bay-a on the course: a parallel slot 1.5 car lengths long between two parked cars
// and the fence. The default search finds no path; the fine search does, and the
// tracker, driving its full-lock arcs on their curvature, parks within tolerance.
// The searches stop at their expansion budgets, not the clock: with 1 ms time
// budgets the run is the same (a sanitizer build is 3–5× slower and once ran out
// of the fine search's 2 s); with closed_loop.planning_budget time they apply.
TEST(RunCliTest, ParksInTheTightParallelBayOfTheCourseWhateverTheClock) {
  const std::string dir = testing::TempDir("run_cli_bay");
  const std::string no_time =
      "--stack truth --set hybrid_astar.time_budget_ms=1 --set hybrid_astar_fine.time_budget_ms=1";
  RunParked("course-loop.yaml", "1", dir + "/out", no_time);
  const auto clocked = testing::RunSpecht("run '" + testing::SourceDir() + "/datasets/scenarios/course-loop.yaml' " +
                                          "--seeds 1 -q -o '" + dir + "/clocked' " + no_time +
                                          " --set closed_loop.planning_budget=time");
  EXPECT_EQ(clocked.exit_code, 1) << clocked.out << clocked.err;
  EXPECT_THAT(clocked.out + clocked.err, HasSubstr("no path within the time budget of 1.000000 ms"));
}

// map_source lidar: the car plans on the map its LiDAR builds as it drives (unknown
// cells free); walls that appear on the path ahead send it back to plan.
TEST(RunCliTest, ParksOnTheMapItsLidarBuildsReplanningAsWallsAppear) {
  const auto report = RunParked("urban-crossing.yaml", "1", testing::TempDir("run_cli_lidar") + "/out",
                                "--stack truth --set closed_loop.map_source=lidar");
  const auto& run = report["runs"][0];
  EXPECT_GE(run["map_replans"].get<int>(), 1);
  bool logged = false;
  for (const auto& t : run["transitions"])
    logged |= t["reason"].get<std::string>().find("the map shows an obstacle on the path") != std::string::npos;
  EXPECT_TRUE(logged);
}

// --stack full drives on what the car perceives: SLAM's pose (scored against the
// simulator: 0.013 m at worst measured on these seeds) and tracks from noisy
// detections (recall 0.90–0.97 per class measured); --stack truth is the oracle.
TEST(RunCliTest, TheFullStackDrivesOnSlamPerceivedTracksAndTheLocalPlannersPaths) {
  const std::string dir = testing::TempDir("run_cli_full");
  const auto report = RunParked("parking-lot.yaml", "101-102", dir + "/full", "--stack full");
  const auto& m = report["metrics"];
  EXPECT_EQ(m["stack"], "full");
  EXPECT_LT(m["localization_ate_max_m"].get<double>(), 0.05);
  EXPECT_LT(m["localization_heading_error_max_deg"].get<double>(), 1.0);
  for (const char* cls : {"pedestrian", "cyclist", "car"}) {
    EXPECT_GE(m["perception"][cls]["recall"].get<double>(), 0.85) << cls;
    EXPECT_GE(m["perception"][cls]["precision"].get<double>(), 0.8) << cls;
  }
  // The OMPL local planner drives: the car follows its paths on all the driving but
  // the final manoeuvres into the bays (which follow hybrid A*'s route).
  const auto& local = m["local_planner"];
  EXPECT_GE(local["share_of_driving_outside_manoeuvres"].get<double>(), 0.9);
  EXPECT_GE(local["success_rate"].get<double>(), 0.8);
  for (const auto& run : report["runs"]) {
    EXPECT_GT(run["local_planner"]["found"].get<int>(), 0);
    EXPECT_LE(run["local_planner"]["max_iterations"].get<int>(), 6000);
  }
  EXPECT_THAT(testing::ReadFile(dir + "/full/steps-101.jsonl"), HasSubstr("\"path\":\"local\""));
  // The first seed's video (closed_loop.video first): the truth beside the world model.
  EXPECT_EQ(report["runs"][0]["video"], "run-101.mp4");
  EXPECT_GT(fs::file_size(dir + "/full/run-101.mp4"), 10000u);
  EXPECT_EQ(report["runs"][1]["video"], "");
  EXPECT_FALSE(fs::exists(dir + "/full/run-102.mp4"));
  // …and its MCAP (closed_loop.mcap first), which replays as a dataset.
  EXPECT_EQ(report["runs"][0]["mcap"], "run-101.mcap");
  const auto replayed =
      testing::RunSpecht("slam -q --no-mcap '" + dir + "/full/run-101.mcap' -o '" + dir + "/replayed'");
  EXPECT_EQ(replayed.exit_code, 0) << replayed.err;
  const auto truth = RunParked("parking-lot.yaml", "101-102", dir + "/truth", "--stack truth");
  EXPECT_EQ(truth["metrics"]["stack"], "truth");
  EXPECT_EQ(truth["metrics"]["localization_ate_max_m"].get<double>(), 0.0);
  EXPECT_EQ(truth["metrics"]["perception"]["pedestrian"]["recall"].get<double>(), 1.0);
}

// A mapping drive leaves SLAM's map of the site (map-<seed>/, in the scenario's
// frame); a later run localises on it and plans on its grid: no truth but the
// scenario's start pose reaches the car (measured on seed 2: 0.015 m at worst).
TEST(RunCliTest, ALaterRunLocalisesOnTheMapAMappingDriveLeft) {
  const std::string dir = testing::TempDir("run_cli_site_map");
  const auto mapping = RunParked("parking-lot.yaml", "1", dir + "/mapping", "--stack full");
  EXPECT_EQ(mapping["runs"][0]["localization"]["mode"], "slam");
  for (const char* f : {"map.yaml", "map.pgm", "map.gridmap", "graph.g2o", "keyframes.rawlog", "site.json", "map.png"})
    EXPECT_TRUE(fs::exists(dir + "/mapping/map-1/" + f)) << f;
  const auto located = RunParked("parking-lot.yaml", "2", dir + "/located", "--map '" + dir + "/mapping/map-1'");
  const auto& run = located["runs"][0];
  EXPECT_EQ(run["localization"]["mode"], "map");
  EXPECT_EQ(run["static_layer"], "site map");
  EXPECT_LT(run["localization"]["ate_max_m"].get<double>(), 0.05);
  EXPECT_EQ(located["inputs"]["map"], dir + "/mapping/map-1");

  // Another scenario's map, or a folder that holds no map: an input error before the car moves.
  const std::string urban = testing::SourceDir() + "/datasets/scenarios/urban-crossing.yaml";
  auto r = testing::RunSpecht("run '" + urban + "' -q -o '" + dir + "/other' --map '" + dir + "/mapping/map-1'");
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_THAT(r.err, HasSubstr("map-1/site.json: the map was drawn in scenario 'parking-lot', this run is in "
                               "'urban-crossing'"));
  r = testing::RunSpecht("run '" + urban + "' -q -o '" + dir + "/other' --map '" + dir + "/mapping'");
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_THAT(r.err, HasSubstr(dir + "/mapping: not a specht map (missing graph.g2o"));
  EXPECT_FALSE(fs::exists(dir + "/other/report.json"));
}

// The emergency check on the LiDAR's raw returns needs neither map nor pose nor
// tracks. A pedestrian stands on the parking lot's path to its bay and perception
// reports nothing (detection_probability 0): without the check the car runs into
// her; with it the returns stop the car, and those neither the map nor a track
// explains become the LiDAR obstacle layer: the next plan goes round her and the car
// parks, once stopped (measured: 2.45 m before her, passing her 0.54 m off).
TEST(RunCliTest, TheLidarStopHaltsTheCarBeforeAPedestrianPerceptionMissesAndItGoesRound) {
  const std::string dir = testing::TempDir("run_cli_lidar_stop");
  std::string scenario = testing::ReadFile(testing::SourceDir() + "/datasets/scenarios/parking-lot.yaml");
  const size_t agents = scenario.find("agents:"), sensors = scenario.find("sensors:");
  ASSERT_NE(sensors, std::string::npos);
  scenario.replace(agents, sensors - agents,
                   "agents:\n  - {id: 1, class: pedestrian, route: [[9.6, 7.1], [9.7, 7.1]], max_speed_mps: 0.01}\n");
  testing::WriteFile(dir + "/standing.yaml", scenario);
  const auto drive = [&](const std::string& name, const std::string& extra) {
    testing::RunSpecht("run '" + dir + "/standing.yaml' --seeds 1 -q -o '" + dir + "/" + name +
                       "' --set synthetic_detections.detection_probability=0 --set closed_loop.time_limit_s=60 " +
                       extra);
    return Report(dir + "/" + name)["runs"][0];
  };
  EXPECT_GT(drive("off", "--set closed_loop.lidar_stop=false")["collisions"].get<int>(), 0)
      << "no contact without the check: the test lost its point";
  const auto on = drive("on", "");
  EXPECT_EQ(on["collisions"].get<int>(), 0);
  EXPECT_TRUE(on["success"].get<bool>()) << on["failure"];
  int stops = 0;
  for (const auto& t : on["transitions"])
    stops += t["reason"].get<std::string>().find("a LiDAR return") != std::string::npos;
  EXPECT_GE(stops, 1);
  EXPECT_LE(stops, 2);
  // Without the obstacle layer every replan leads back to her.
  const auto forgetful = drive("forgetful", "--set closed_loop.lidar_obstacle_range_m=0");
  EXPECT_FALSE(forgetful["success"].get<bool>());
  EXPECT_EQ(forgetful["collisions"].get<int>(), 0);
}

// A kidnapped pose (2 m ahead and 20° off from 4 s on, as a wrong relocalisation)
// is noticed by the pose check against the prior map: the car stops, relocalises on
// the map and parks within tolerance by the truth. Measured on seed 1: noticed 0.5 s
// after the kidnap, relocalised 0.1 s later to 0.05 m / 0.1° of the true pose.
TEST(RunCliTest, AKidnappedPoseIsNoticedTheCarStopsRelocalisesAndParks) {
  const auto report = RunParked("parking-lot.yaml", "1", testing::TempDir("run_cli_kidnap") + "/out",
                                "--stack full --set closed_loop.kidnap_at_s=4");
  const auto& run = report["runs"][0];
  const auto& check = run["localization"]["pose_check"];
  EXPECT_GE(check["lost"].get<int>(), 1);
  EXPECT_GE(check["relocalized"].get<int>(), 1);
  double lost_at = -1, relocalized_at = -1;
  for (const auto& t : run["transitions"]) {
    if (t["to"] == "localization_lost" && lost_at < 0) lost_at = t["t_s"].get<double>();
    if (t["from"] == "localization_lost" && t["to"] == "plan" && relocalized_at < 0)
      relocalized_at = t["t_s"].get<double>();
  }
  EXPECT_GE(lost_at, 4.0);
  EXPECT_LE(lost_at, 5.0);  // five scans at 10 Hz
  EXPECT_GE(relocalized_at, lost_at);
  EXPECT_LE(relocalized_at, lost_at + 1.0);
  // After the relocalisation the believed pose is back within the parking tolerance.
  double worst_after = 0;
  std::istringstream steps(testing::ReadFile(testing::TempDir("run_cli_kidnap") + "/out/steps-1.jsonl"));
  for (std::string line; std::getline(steps, line);) {
    const auto k = nlohmann::json::parse(line);
    if (k["t_s"].get<double>() < relocalized_at + 0.2) continue;
    const auto& b = k["believed"];
    worst_after = std::max(worst_after, std::hypot(k["x_m"].get<double>() - b[0].get<double>(),
                                                   k["y_m"].get<double>() - b[1].get<double>()));
  }
  EXPECT_LT(worst_after, 0.1);
  // Without the check the car drives on the wrong pose.
  const std::string off = testing::TempDir("run_cli_kidnap") + "/off";
  testing::RunSpecht("run '" + testing::SourceDir() + "/datasets/scenarios/parking-lot.yaml' --seeds 1 -q -o '" + off +
                     "' --stack full --set closed_loop.kidnap_at_s=4 --set pose_check.enabled=false --set "
                     "closed_loop.time_limit_s=60");
  const auto unchecked = Report(off)["runs"][0];
  EXPECT_FALSE(unchecked["success"].get<bool>()) << "the kidnap did no harm unnoticed: the test lost its point";
}

// A blind camera (no perception frame from 4 s for 3 s): the car slows once the
// latest frame is blind_slow_s old, stops as blind after blind_stop_s, and drives on
// once frames have come again for the tracker's confirmation window (5 frames).
TEST(RunCliTest, ABlindSensorSlowsThenStopsTheCarUntilFramesReturn) {
  const auto report = RunParked("parking-lot.yaml", "1", testing::TempDir("run_cli_blind") + "/out",
                                "--stack full --set closed_loop.blind_at_s=4 --set closed_loop.blind_for_s=3");
  const auto& run = report["runs"][0];
  double blind_at = -1, restored_at = -1;
  for (const auto& t : run["transitions"]) {
    if (t["to"] == "blind" && blind_at < 0) blind_at = t["t_s"].get<double>();
    if (t["from"] == "blind" && restored_at < 0) restored_at = t["t_s"].get<double>();
  }
  EXPECT_NEAR(blind_at, 4.0 + 0.4, 0.11);  // blind_stop_s after the last frame
  EXPECT_NEAR(restored_at, 7.5, 0.11);     // the confirmation window (5 frames) after the first frame
  // While frames were late but not yet missing long enough to stop, the car slowed
  // (it waits for a cyclist at the start of seed 1, so it may not have been moving).
  std::istringstream steps(testing::ReadFile(testing::TempDir("run_cli_blind") + "/out/steps-1.jsonl"));
  for (std::string line; std::getline(steps, line);) {
    const auto k = nlohmann::json::parse(line);
    const double t = k["t_s"].get<double>();
    if (t > blind_at + 0.5 && t < restored_at) {  // braces: EXPECT_EQ is an if/else inside
      EXPECT_EQ(k["state"], "blind") << t;
    }
  }
}

// closed_loop.perception camera: our SGM and the CNN on the simulator's rendered
// stereo frames (photographed agents), fused at the believed pose, tracked. The first
// 8 s of parking-lot seed 1: a frame every 0.1 s, the pedestrians found by tracks
// (measured 0.94 recall, 0.99 precision), and the same seed drives the same steps.
TEST(RunCliTest, TheCameraPerceivesTheRoadUsersInTheLoop) {
  if (testing::DataDir().empty()) SPECHT_SKIP() << "no data dir (detector models, sprites)";
  const std::string dir = testing::TempDir("run_cli_camera");
  const auto drive = [&](const std::string& name) {
    testing::RunSpecht("run '" + testing::SourceDir() + "/datasets/scenarios/parking-lot.yaml' --seeds 1 -q -o '" +
                       dir + "/" + name + "' --data-dir '" + testing::DataDir() +
                       "' --set closed_loop.perception=camera --set perception.stereo_downsample=2 "
                       "--set closed_loop.time_limit_s=8");
    return Report(dir + "/" + name)["runs"][0];
  };
  const auto run = drive("a");
  const auto& seen = run["perception"];
  EXPECT_EQ(seen["mode"], "camera");
  EXPECT_NEAR(seen["frames"].get<double>(), 80, 2);
  const auto& pedestrians = seen["by_class"]["pedestrian"];
  EXPECT_GE(pedestrians["in_view"].get<int>(), 40);
  EXPECT_GE(pedestrians["recall"].get<double>(), 0.8);
  EXPECT_GE(pedestrians["precision"].get<double>(), 0.8);
  EXPECT_TRUE(run["timing"]["stage_ms_per_s"].contains("render"));
  drive("b");
  EXPECT_EQ(testing::ReadFile(dir + "/a/steps-1.jsonl"), testing::ReadFile(dir + "/b/steps-1.jsonl"));
}

// A run is a replay: the same seed gives the same report figures and per-step poses
// (all but the wall-clock times: the planners', the local planner's, the stages').
TEST(RunCliTest, TheSameSeedDrivesTheSameRun) {
  const std::string dir = testing::TempDir("run_cli_again");
  auto a = RunParked("parking-lot.yaml", "103", dir + "/a", "--stack full")["runs"][0];
  auto b = RunParked("parking-lot.yaml", "103", dir + "/b", "--stack full")["runs"][0];
  for (auto* run : {&a, &b}) run->erase("planning_ms"), run->erase("timing"), (*run)["local_planner"].erase("ms");
  EXPECT_EQ(a.dump(), b.dump());
  EXPECT_EQ(testing::ReadFile(dir + "/a/steps-103.jsonl"), testing::ReadFile(dir + "/b/steps-103.jsonl"));
}

// The camera in the loop without its inputs: the missing file is named and the car
// never moves (no run directory is written).
TEST(RunCliTest, TheCameraWithoutSpritesOrModelsNamesTheMissingFile) {
  const std::string dir = testing::TempDir("run_cli_camera_bad");
  std::filesystem::create_directories(dir + "/data");
  const auto r = testing::RunSpecht("run '" + testing::SourceDir() + "/datasets/scenarios/parking-lot.yaml' -q -o '" +
                                    dir + "/out' --data-dir '" + dir + "/data' --set closed_loop.perception=camera");
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_THAT(r.err, HasSubstr(dir + "/data/sprites"));
  EXPECT_FALSE(fs::exists(dir + "/out/report.json"));
}

TEST(RunCliTest, BadMissionNamesTheLine) {
  const std::string dir = testing::TempDir("run_cli_bad");
  testing::WriteFile(dir + "/mission.yaml", "goals:\n  - park: bay-z\n");
  const std::string scenario = testing::SourceDir() + "/datasets/scenarios/parking-lot.yaml";
  const auto r =
      testing::RunSpecht("run '" + scenario + "' --mission '" + dir + "/mission.yaml' -q -o '" + dir + "/out'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("mission.yaml:2: scenario parking-lot has no bay 'bay-z'"));
}

}  // namespace
}  // namespace specht
