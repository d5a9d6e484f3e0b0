// `specht replay` with the perception pipeline: a simulated drive whose stereo frames
// are replaced by the real KITTI object pair, so the detector has cars to find; they
// land in the report, the tracker, the world model's snapshots and the map picture.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <opencv2/videoio.hpp>
#include <set>
#include <sstream>

#include "report.h"
#include "specht/io/object_tracks.h"
#include "test_support.h"

namespace specht {
namespace {

namespace fs = std::filesystem;

// The urban crossing, whose camera is like KITTI's (1242×375, f = 721.5 px, 0.54 m)
// so that KITTI's frames can stand in for the rendered ones, at 1 Hz.
std::string KittiCameraScenario(const std::string& dir) {
  std::string yaml = testing::ReadFile(testing::SourceDir() + "/datasets/scenarios/urban-crossing.yaml");
  const std::string from = "stereo: {rate_hz: 10, width: 1242, height: 375, focal_px: 721.5, baseline_m: 0.54,";
  const auto at = yaml.find(from);
  EXPECT_NE(at, std::string::npos) << "the scenario's camera line changed";
  yaml.replace(at, from.size(), "stereo: {rate_hz: 1, width: 1242, height: 375, focal_px: 721.5, baseline_m: 0.54,");
  testing::WriteFile(dir + "/urban-crossing-kitti.yaml", yaml);
  return dir + "/urban-crossing-kitti.yaml";
}

TEST(PerceptionReplayTest, StereoFramesBecomeObstaclesInTheWorldModel) {
  const std::string data = testing::DataDir();
  SPECHT_REQUIRE_FILE(data.empty() || !fs::exists(data + "/models") ? std::string() : data);
  const std::string base = testing::TempDir(), sim = base + "/sim", out = base + "/replay";
  ASSERT_EQ(testing::RunSpecht("sim -q '" + KittiCameraScenario(base) + "' --duration 6 -o '" + sim + "'").exit_code,
            0);
  for (const char* side : {"left", "right"})
    fs::copy_file(data + "/stereo/kitti_object/" + side + ".png", sim + "/sim_Images/" + side + "_000003.png",
                  fs::copy_options::overwrite_existing);
  const auto r = testing::RunSpecht("replay -q '" + sim + "/sim.rawlog' --data-dir '" + data + "' -o '" + out + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = Report(out);
  ASSERT_TRUE(report.contains("perception")) << report.dump();
  EXPECT_EQ(report["perception"]["frames"], 6);
  EXPECT_GE(report["perception"]["detections"].get<int>(), 4);
  EXPECT_GE(report["perception"]["obstacles"].get<int>(), 4);
  EXPECT_TRUE(fs::exists(out + "/world.json"));
  const auto world = nlohmann::json::parse(testing::ReadFile(out + "/world.json"));
  EXPECT_TRUE(world.contains("static_map"));
  EXPECT_GT(world["cost"]["lethal"].get<int>(), 0);

  // Every snapshot holds the layers of one frame: obstacles, tracks and OctoMap of
  // its stamp, a static map not newer than it; snapshots every 0.5 s of data time.
  std::istringstream lines(testing::ReadFile(out + "/snapshots.jsonl"));
  int snapshots = 0;
  for (std::string line; std::getline(lines, line); ++snapshots) {
    const auto snap = nlohmann::json::parse(line);
    const double t = snap["stamp_s"], static_t = snap["layer_stamps_s"]["static"];
    EXPECT_EQ(snap["layer_stamps_s"]["obstacles"].get<double>(), t) << line.substr(0, 300);
    EXPECT_EQ(snap["layer_stamps_s"]["tracks"].get<double>(), t);
    EXPECT_EQ(snap["layer_stamps_s"]["octree"].get<double>(), t);
    EXPECT_LE(static_t, t);
    if (snapshots > 0) {
      EXPECT_GT(static_t, 0);  // the first frame may come before the first map
    }
    EXPECT_GT(snap["octree"]["leaves"].get<int>(), 100);
    for (const auto& o : snap["obstacles"]) EXPECT_LE(o["stamp_s"].get<double>(), t);
  }
  EXPECT_EQ(snapshots, 6);
  EXPECT_EQ(report["perception"]["frames_at_held_pose"], 0);

  // perception.mode off leaves it out.
  const auto off = testing::RunSpecht("replay -q '" + sim + "/sim.rawlog' --data-dir '" + data +
                                      "' --set perception.mode=off -o '" + out + "-off'");
  ASSERT_EQ(off.exit_code, 0) << off.err;
  EXPECT_FALSE(Report(out + "-off").contains("perception"));
  EXPECT_FALSE(fs::exists(out + "-off/tracks.csv"));
}

// The same KITTI pair in five frames in a row: the detector's cars become confirmed
// tracks of class car in tracks.csv and in the world model's track layer; the
// replay is deterministic to the byte.
TEST(PerceptionReplayTest, DetectionsBecomeTracksInTheWorldModel) {
  const std::string data = testing::DataDir();
  SPECHT_REQUIRE_FILE(data.empty() || !fs::exists(data + "/models") ? std::string() : data);
  const std::string base = testing::TempDir(), sim = base + "/sim", out = base + "/replay";
  ASSERT_EQ(testing::RunSpecht("sim -q '" + KittiCameraScenario(base) + "' --duration 8 -o '" + sim + "'").exit_code,
            0);
  for (int k = 2; k <= 6; ++k)
    for (const char* side : {"left", "right"})
      fs::copy_file(data + "/stereo/kitti_object/" + side + ".png",
                    sim + "/sim_Images/" + side + "_00000" + std::to_string(k) + ".png",
                    fs::copy_options::overwrite_existing);
  const std::string replay =
      "replay -q '" + sim + "/sim.rawlog' --data-dir '" + data + "' --set perception.octree=false -o '";
  const auto r = testing::RunSpecht(replay + out + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = Report(out);
  EXPECT_GE(report["perception"]["tracks_confirmed"].get<int>(), 2) << report["perception"].dump();

  const std::string csv = testing::ReadFile(out + "/tracks.csv");
  EXPECT_THAT(csv, ::testing::StartsWith("id,t_s,x_m,y_m,class\n"));
  EXPECT_THAT(csv, ::testing::HasSubstr(",car\n"));
  bool tracks_in_world = false;
  std::istringstream lines(testing::ReadFile(out + "/snapshots.jsonl"));
  for (std::string line; std::getline(lines, line);) {
    const auto snap = nlohmann::json::parse(line);
    for (const auto& t : snap["tracks"]) {
      if (t["state"] == "confirmed" && t["class"] == "car") tracks_in_world = true;
      EXPECT_FALSE(t["prediction"].empty());
    }
    EXPECT_FALSE(snap.contains("octree"));
  }
  EXPECT_TRUE(tracks_in_world);

  ASSERT_EQ(testing::RunSpecht(replay + out + "-again'").exit_code, 0);
  EXPECT_EQ(testing::ReadFile(out + "-again/tracks.csv"), csv);
  EXPECT_EQ(testing::ReadFile(out + "-again/snapshots.jsonl"), testing::ReadFile(out + "/snapshots.jsonl"));
  // The pipelined run (sensing and mapping on worker threads) is the sequential one.
  ASSERT_EQ(testing::RunSpecht(replay + out + "-sequential' --set perception.pipelined=false").exit_code, 0);
  EXPECT_EQ(testing::ReadFile(out + "-sequential/tracks.csv"), csv);
  EXPECT_EQ(testing::ReadFile(out + "-sequential/snapshots.jsonl"), testing::ReadFile(out + "/snapshots.jsonl"));
}

// A drive with the photographed agents at the camera's 10 Hz, replayed with a
// trajectory classifier trained on simulated tracker output (windows of 16 points):
// each confirmed track old enough gets class probabilities — in tracks.csv, summing
// to one, kept once it has them (the mean over its windows) — and both videos hold
// one frame per stereo frame. A model directory that holds no model is refused
// before anything is written.
TEST(PerceptionReplayTest, TheClassifierLabelsTracksAndTheVideosShowTheDrive) {
  const std::string data = testing::DataDir();
  SPECHT_REQUIRE_FILE(data.empty() || !fs::exists(data + "/models") || !fs::exists(data + "/sprites") ? std::string()
                                                                                                      : data);
  const std::string base = testing::TempDir(), scenarios = testing::SourceDir() + "/datasets/scenarios";
  const std::string course = scenarios + "/course-loop.yaml";
  ASSERT_EQ(testing::RunSpecht("track '" + course + "' --seeds 1-2 -q -o '" + base + "/tracks'").exit_code, 0);
  ASSERT_EQ(
      testing::RunSpecht("classify prepare '" + base + "/tracks/tracks.csv' --scenario '" + course +
                         "' --set classify.length=16 --set 'classify.features=[x,y,dt,speed,course,accel,turn_rate,"
                         "dist_static]' -q -o '" +
                         base + "/data'")
          .exit_code,
      0);
  ASSERT_EQ(
      testing::RunSpecht("classify train '" + base + "/data' --set classify_model.epochs=1 -q -o '" + base + "/model'")
          .exit_code,
      0);
  ASSERT_EQ(testing::RunSpecht("sim -q '" + course + "' --duration 5 --data-dir '" + data + "' --sprites tuning -o '" +
                               base + "/sim'")
                .exit_code,
            0);
  const std::string replay = "replay -q '" + base + "/sim/sim.rawlog' --data-dir '" + data + "' --model '";
  const auto r = testing::RunSpecht(replay + base + "/model' -o '" + base + "/replay'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = Report(base + "/replay");
  EXPECT_GT(report["perception"]["windows_classified"].get<int>(), 0) << report["perception"].dump();

  const auto tracks = io::ReadObjectTracks(base + "/replay/tracks.csv");
  EXPECT_THAT(testing::ReadFile(base + "/replay/tracks.csv"),
              ::testing::StartsWith("id,t_s,x_m,y_m,class,p_car,p_cyclist,p_pedestrian\n"));
  std::set<std::string> classified;
  for (const auto& s : tracks) {
    if (s.class_probabilities.empty()) {
      EXPECT_FALSE(classified.count(s.id)) << s.id << " lost its probabilities at " << s.t_s;
      continue;
    }
    classified.insert(s.id);
    double sum = 0;
    for (const auto& [cls, p] : s.class_probabilities) sum += p;
    EXPECT_NEAR(sum, 1.0, 2e-4) << s.id << " at " << s.t_s;
  }
  EXPECT_FALSE(classified.empty());

  const int frames = report["perception"]["frames"].get<int>();
  for (const auto& [name, size] :
       {std::pair{"camera.mp4", cv::Size(1242, 374)}, {"birds_eye.mp4", cv::Size(600, 600)}}) {
    cv::VideoCapture video(base + "/replay/" + name);
    ASSERT_TRUE(video.isOpened()) << name;
    int n = 0;
    for (cv::Mat f; video.read(f); ++n) ASSERT_EQ(f.size(), size) << name;
    EXPECT_EQ(n, frames) << name;
  }

  fs::create_directories(base + "/empty");
  const auto bad = testing::RunSpecht(replay + base + "/empty' -o '" + base + "/bad'");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_THAT(bad.err, ::testing::HasSubstr(base + "/empty/model.json: cannot open"));
  EXPECT_FALSE(fs::exists(base + "/bad/params.yaml"));
}

}  // namespace
}  // namespace specht
