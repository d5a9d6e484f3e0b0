// The pipeline's own pieces: the pose at a camera frame's stamp between two scans,
// the checks on a stereo observation's calibration, the online classifier's averaging.
#include <mrpt/obs/CObservationStereoImages.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "specht/classify/model.h"
#include "specht/classify/trajectory_classifier.h"
#include "specht/core/error.h"
#include "specht/pipeline/online_classifier.h"
#include "specht/pipeline/perception_eval.h"
#include "specht/pipeline/pose_history.h"
#include "specht/pipeline/stereo_perception.h"
#include "test_support.h"

namespace specht::pipeline {
namespace {

using mrpt::poses::CPose3D;
using ::testing::HasSubstr;

Stamp At(double s) { return Stamp::FromSeconds(100 + s); }

TEST(PoseHistoryTest, AFrameBetweenTwoScansGetsThePoseInterpolatedAtItsStamp) {
  PoseHistory h;
  EXPECT_FALSE(h.At(At(0)).has_value());
  h.Add(At(0.0), CPose3D(0, 0, 0, 0, 0, 0));
  h.Add(At(0.1), CPose3D(1.0, 2.0, 0, 0.2, 0, 0));
  EXPECT_FALSE(h.Covers(At(0.15)));
  EXPECT_TRUE(h.Covers(At(0.1)));
  const CPose3D p = *h.At(At(0.025));  // a quarter of the way
  EXPECT_NEAR(p.x(), 0.25, 1e-9);
  EXPECT_NEAR(p.y(), 0.5, 1e-9);
  EXPECT_NEAR(p.yaw(), 0.05, 1e-9);
  // Before the first and after the last: held, not extrapolated.
  EXPECT_NEAR(h.At(At(-1))->x(), 0.0, 1e-12);
  EXPECT_NEAR(h.At(At(5))->x(), 1.0, 1e-12);
  EXPECT_THROW(h.Add(At(0.05), CPose3D()), RuntimeError);
}

TEST(PoseHistoryTest, HeadingIsInterpolatedTheShortWayRoundThePi) {
  const CPose3D a(0, 0, 0, 170 * M_PI / 180, 0, 0), b(0, 0, 0, -170 * M_PI / 180, 0, 0);
  EXPECT_NEAR(std::abs(Interpolate(a, b, 0.5).yaw()), M_PI, 1e-9);
  EXPECT_NEAR(Interpolate(a, b, 0.25).yaw(), 175 * M_PI / 180, 1e-9);
}

TEST(PoseHistoryTest, OldPosesAreDropped) {
  PoseHistory h(1.0);
  for (int k = 0; k <= 50; ++k) h.Add(At(0.1 * k), CPose3D(k, 0, 0, 0, 0, 0));
  EXPECT_NEAR(h.At(At(0))->x(), 40.0, 1e-9);  // the oldest kept: 1 s before the newest
}

mrpt::obs::CObservationStereoImages Calibrated(int width, int height) {
  mrpt::obs::CObservationStereoImages obs;
  obs.sensorLabel = "STEREO";
  for (auto* cam : {&obs.leftCamera, &obs.rightCamera}) {
    cam->ncols = width, cam->nrows = height;
    cam->setIntrinsicParamsFromValues(400, 400, width / 2.0, height / 2.0);
  }
  obs.rightCameraPose = mrpt::poses::CPose3DQuat(CPose3D(0.4, 0, 0, 0, 0, 0));
  return obs;
}

TEST(StereoPerceptionTest, TheCameraComesFromTheObservationsCalibration) {
  const stereo::RectifiedCamera c = CameraOf(Calibrated(640, 240), {640, 240});
  EXPECT_EQ(c.focal_px, 400);
  EXPECT_EQ(c.cx_px, 320);
  EXPECT_NEAR(c.baseline_m, 0.4, 1e-12);
}

TEST(StereoPerceptionTest, AMissingOrContradictoryCalibrationIsNamed) {
  const auto message = [](const mrpt::obs::CObservationStereoImages& obs, cv::Size size) {
    try {
      CameraOf(obs, size);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  auto no_focal = Calibrated(640, 240);
  no_focal.leftCamera.setIntrinsicParamsFromValues(0, 0, 320, 120);
  EXPECT_THAT(message(no_focal, {640, 240}), HasSubstr("'STEREO'"));
  EXPECT_THAT(message(no_focal, {640, 240}), HasSubstr("leftCamera: no focal length"));
  auto no_baseline = Calibrated(640, 240);
  no_baseline.rightCameraPose = mrpt::poses::CPose3DQuat(CPose3D());
  EXPECT_THAT(message(no_baseline, {640, 240}), HasSubstr("rightCameraPose: no baseline"));
  EXPECT_THAT(message(Calibrated(640, 240), {1242, 375}),
              HasSubstr("leftCamera: intrinsics for 640x240 but the image is 1242x375"));
  auto off_centre = Calibrated(640, 240);
  off_centre.leftCamera.setIntrinsicParamsFromValues(400, 400, 900, 120);
  EXPECT_THAT(message(off_centre, {640, 240}), HasSubstr("principal point (900"));
}

// A drive's truth files that are not what `specht sim` writes are refused with the
// file and line: a wrong header, a short row, a field that is not a number.
TEST(PerceptionEvalTest, MalformedTruthFilesNameFileAndLine) {
  const std::string dir = testing::TempDir();
  std::filesystem::create_directories(dir + "/stereo");
  const auto message = [&](const std::string& agents_csv) {
    testing::WriteFile(dir + "/stereo/agents.csv", agents_csv);
    try {
      EvaluatePerceivedTracks(dir, dir, {});
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string header = "frame,t_s,id,class,sprite,x0_px,y0_px,x1_px,y1_px,visible,truncated,range_m\n";
  EXPECT_THAT(message("frame,id\n"), HasSubstr("agents.csv:1: not the header of stereo/agents.csv"));
  EXPECT_THAT(message(header + "0,0.1,3,Car,,1,2,3\n"), HasSubstr("agents.csv:2: expected 12 fields, found 8"));
  EXPECT_THAT(message(header + "0,0.1,3,Car,,1,2,3,4,x,0,5\n"), HasSubstr("agents.csv:2: a field is not a number"));
  EXPECT_THAT(message(header), HasSubstr(dir + "/agents.csv: cannot open"));
}

// A confirmed track walking at `speed` along x, `n` points at 10 Hz up to `t_end`.
types::Track Walker(long id, double speed, int n, double t_end) {
  types::Track t;
  t.id = id;
  t.state = "confirmed";
  for (int i = 0; i < n; ++i) {
    const double ts = t_end - 0.1 * (n - 1 - i);
    t.history.push_back({Stamp::FromSeconds(ts), speed * ts, 0.3 * std::sin(ts)});
  }
  t.stamp = t.history.back().stamp;
  return t;
}

// Averaged over the track, a track's probabilities are the mean of the answers its
// latest windows got frame by frame; a coasting track keeps its mean; a track too
// short for a window gets none; each frame's answers sum to one.
TEST(OnlineClassifierTest, ATracksProbabilitiesAreTheMeanOverItsWindows) {
  const std::string dir = testing::TempDir("online_classifier");
  classify::PreprocessOptions pre;
  pre.length = 8;
  pre.features = {"x", "y", "speed", "turn_rate"};
  classify::ModelOptions small;
  small.threads = 1;
  classify::Classifier network(small, 4, 8, {"fast", "slow"});  // untrained: any answers will do
  network.Save(dir + "/model", {{"preprocessing", classify::PreprocessingJson(pre, {})}});
  const auto model =
      std::make_shared<classify::TrajectoryClassifier>(classify::TrajectoryClassifier::Load(dir + "/model"));
  OnlineClassifier latest(model, OnlineClassifier::Averaging::kLatest),
      mean(model, OnlineClassifier::Averaging::kTrack);

  std::map<std::string, double> sum;
  std::vector<double> fast;  // the latest answers, which must differ for the test to tell a mean from the last
  int frames = 0;
  for (int k = 0; k < 4; ++k) {
    const double t = 10 + 0.1 * k;
    std::vector<types::Track> a = {Walker(1, 1.5 + k, 12 + k, t), Walker(2, 1, 3, t)}, b = a;
    latest.Update(a, {});
    mean.Update(b, {});
    ASSERT_EQ(a[0].class_probabilities.size(), 2u);
    EXPECT_NEAR(a[0].class_probabilities["fast"] + a[0].class_probabilities["slow"], 1.0, 1e-5);
    EXPECT_TRUE(a[1].class_probabilities.empty()) << "3 points make no window of 8";
    EXPECT_TRUE(b[1].class_probabilities.empty());
    for (const auto& [cls, p] : a[0].class_probabilities) sum[cls] += p;
    fast.push_back(a[0].class_probabilities["fast"]);
    ++frames;
    for (const auto& [cls, p] : b[0].class_probabilities)
      EXPECT_NEAR(p, sum[cls] / frames, 1e-6) << cls << " frame " << k;
  }
  std::vector<types::Track> coasting = {Walker(1, 9, 2, 11)};
  coasting[0].state = "coasting";
  mean.Update(coasting, {});
  for (const auto& [cls, p] : coasting[0].class_probabilities) EXPECT_NEAR(p, sum[cls] / frames, 1e-6) << cls;
  EXPECT_EQ(mean.windows(), 4);
  EXPECT_GT(*std::max_element(fast.begin(), fast.end()) - *std::min_element(fast.begin(), fast.end()), 1e-4);
}

}  // namespace
}  // namespace specht::pipeline
