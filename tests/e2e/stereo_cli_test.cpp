// `specht stereo` and `specht eval stereo` as a user runs them.
#include <filesystem>
#include <nlohmann/json.hpp>

#include "report.h"
#include "test_support.h"

namespace specht {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

std::string StereoDir() {
  const std::string dir = testing::DataDir() + "/stereo";
  return !testing::DataDir().empty() && fs::is_directory(dir) ? dir : "";
}

TEST(StereoCliTest, LidarGuidedRunWritesDisparityDepthCloudAndOctomap) {
  SPECHT_REQUIRE_FILE(StereoDir());
  const std::string base = testing::TempDir();
  const std::string in = StereoDir() + "/kitti_object/", out = base + "/run";
  const auto r = testing::RunSpecht("stereo -q '" + in + "left.png' '" + in + "right.png' --calib '" + in +
                                    "calib.txt' --lidar '" + in + "lidar.bin' -o '" + out + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* f : {"disparity.png", "disparity_color.png", "hints.png", "depth.png", "depth_color.png",
                        "points.ply", "octomap.bt", "params.yaml", "report.json", "report.md"})
    EXPECT_TRUE(fs::exists(out + "/" + f)) << f;
  const auto report = Report(out);
  EXPECT_GT(report["metrics"]["match"]["density"].get<double>(), 0.6);
  EXPECT_GT(report["metrics"]["unguided"]["lr_consistency"].get<double>(), 0.7);
  EXPECT_GT(report["metrics"]["points"].get<long>(), 100000);
  EXPECT_THAT(r.out, HasSubstr("left-right consistency"));

  // Scored against the KITTI ground truth of another frame: eval stereo runs and
  // reports the figures; its own disparity against itself is perfect.
  const std::string eval_out = base + "/eval";
  const auto e = testing::RunSpecht("eval stereo --estimate '" + out + "/disparity.png' --truth '" + out +
                                    "/disparity.png' -o '" + eval_out + "'");
  ASSERT_EQ(e.exit_code, 0) << e.err;
  EXPECT_THAT(e.out, HasSubstr("D1 0.00 %"));
  EXPECT_TRUE(fs::exists(eval_out + "/error.png"));
}

TEST(StereoCliTest, KittiFrameScoredWithFilledHoles) {
  SPECHT_REQUIRE_FILE(StereoDir());
  const std::string in = StereoDir() + "/kitti2015/", out = testing::TempDir() + "/run";
  ASSERT_EQ(testing::RunSpecht("stereo -q '" + in + "image_2/000000_10.png' '" + in + "image_3/000000_10.png' -o '" +
                               out + "'")
                .exit_code,
            0);
  const auto e = testing::RunSpecht("eval stereo --fill-holes --estimate '" + out + "/disparity.png' --truth '" + in +
                                    "disp_occ_0/000000_10.png' -o '" + out + "/eval'");
  ASSERT_EQ(e.exit_code, 0) << e.err;
  const auto report = Report(out + "/eval");
  EXPECT_LT(report["metrics"]["d1_all"].get<double>(), 0.080);  // 7.43 % measured
  EXPECT_GT(report["metrics"]["density_gt"].get<double>(), 0.99);
}

TEST(StereoCliTest, BadInputExitsTwoWithTheReason) {
  SPECHT_REQUIRE_FILE(StereoDir());
  const std::string k = StereoDir() + "/kitti2015/", m = StereoDir() + "/middlebury_aloe/";
  const std::string out = testing::TempDir() + "/bad";
  struct Case {
    std::string args, message;
  };
  const Case cases[] = {
      {"'" + k + "image_2/000000_10.png' '" + m + "aloeR.jpg'", "differs from the left image"},
      {"'" + k + "disp_occ_0/000000_10.png' '" + k + "image_3/000000_10.png'", "expected an 8-bit image"},
      {"'" + k + "image_2/000000_10.png' '" + k + "image_3/000000_10.png' --hints '" + m + "aloeGT.png'",
       "hints are 1282×1110"},
      {"'" + k + "image_2/000000_10.png' '" + k + "image_3/000000_10.png' --lidar x.bin", "--lidar needs --calib"},
      {"'" + k + "image_2/000000_10.png' '" + k + "image_3/000000_10.png' --calib nowhere.txt", "no such calibration"},
      {"'" + k + "image_2/000000_10.png' '" + k + "image_3/000000_10.png' --set stereo.num_disparities=40",
       "multiple of 16"},
  };
  for (const Case& c : cases) {
    const auto r = testing::RunSpecht("stereo -q " + c.args + " -o '" + out + "'");
    EXPECT_EQ(r.exit_code, 2) << c.args;
    EXPECT_THAT(r.err, HasSubstr(c.message)) << c.args;
    EXPECT_FALSE(fs::exists(out + "/disparity.png")) << c.args;
  }
}

}  // namespace
}  // namespace specht
