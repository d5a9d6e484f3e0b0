// `specht detect` as a user runs it.
#include <filesystem>
#include <nlohmann/json.hpp>

#include "test_support.h"

namespace specht {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

TEST(DetectCliTest, StereoFramesGiveLabelsWithDistances) {
  const std::string data = testing::DataDir();
  SPECHT_REQUIRE_FILE(data.empty() || !fs::exists(data + "/models") ? std::string() : data);
  const std::string k = data + "/stereo/kitti_object/", out = testing::TempDir() + "/run";
  const auto r = testing::RunSpecht("detect -q '" + k + "left.png' --right '" + k + "right.png' --calib '" + k +
                                    "calib.txt' --data-dir '" + data + "' -o '" + out + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* f : {"labels/left.txt", "annotated/left.png", "detections.json", "report.json", "params.yaml"})
    EXPECT_TRUE(fs::exists(out + "/" + f)) << f;
  const auto detections = nlohmann::json::parse(testing::ReadFile(out + "/detections.json"));
  int cars_with_distance = 0;
  for (const auto& d : detections)
    if (d["class"] == "car" && d.contains("distance_m")) ++cars_with_distance;
  EXPECT_GE(cars_with_distance, 4);
  EXPECT_THAT(testing::ReadFile(out + "/labels/left.txt"), HasSubstr("Car -1 -1 -10 "));

  // Bad input: a model that is not there, right images without calibration.
  const auto missing = testing::RunSpecht("detect -q '" + k + "left.png' --data-dir '" + data +
                                          "' --set detect.model=models/none.onnx -o '" + out + "2'");
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_THAT(missing.err, HasSubstr("none.onnx: model not found"));
  const auto no_calib = testing::RunSpecht("detect -q '" + k + "left.png' --right '" + k + "right.png' --data-dir '" +
                                           data + "' -o '" + out + "3'");
  EXPECT_EQ(no_calib.exit_code, 2);
  EXPECT_THAT(no_calib.err, HasSubstr("--right needs --calib"));
}

}  // namespace
}  // namespace specht
