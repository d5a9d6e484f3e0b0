// The detectors on real frames against hand-drawn boxes, box depth against ground
// truth, and bad input.
//
// The expected boxes were drawn by hand: each image was rendered with a 50 px grid
// (red lines every 100 px) and the extent of every clearly visible car at least
// 50 px tall was read off the grid, to about ±5 px. Truncated cars end at the border.
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "specht/core/error.h"
#include "specht/detect/detector.h"
#include "specht/detect/fusion.h"
#include "specht/stereo/calibration.h"
#include "specht/stereo/images.h"
#include "specht/stereo/point_cloud.h"
#include "specht/stereo/sgm.h"
#include "test_support.h"

namespace specht::detect {
namespace {

using ::testing::HasSubstr;

struct HandBoxes {
  std::string image;  // relative to <data>/stereo
  std::vector<cv::Rect2d> cars;
};

cv::Rect2d Box(double x0, double y0, double x1, double y1) {
  return cv::Rect2d(cv::Point2d(x0, y0), cv::Point2d(x1, y1));
}

const std::vector<HandBoxes>& Expected() {
  static const std::vector<HandBoxes> expected = {
      {"kitti2015/image_2/000000_10.png", {Box(168, 177, 382, 302), Box(905, 198, 1242, 375)}},
      {"kitti2015/image_2/000001_10.png", {Box(52, 198, 238, 290)}},
      {"kitti_object/left.png",
       {Box(826, 190, 1242, 375), Box(735, 185, 905, 305), Box(685, 180, 770, 250), Box(470, 180, 542, 233)}},
  };
  return expected;
}

std::string ModelsDir() {
  const std::string dir = testing::DataDir() + "/models";
  return !testing::DataDir().empty() && std::filesystem::is_directory(dir) ? dir : "";
}

// Acceptance 1: both shipped models find the cars in view.
TEST(DetectorTest, BothModelsFindTheHandBoxedCars) {
  SPECHT_REQUIRE_FILE(ModelsDir());
  for (const char* model : {"yolo-fastest", "fastestdet"}) {
    Detector detector(ShippedModel(model), testing::DataDir());
    int found = 0, total = 0;
    for (const auto& frame : Expected()) {
      const cv::Mat image = cv::imread(testing::DataDir() + "/stereo/" + frame.image);
      const auto detections = detector.Detect(image);
      for (const auto& truth : frame.cars) {
        double best = 0;
        for (const auto& d : detections)
          if (d.cls == "car") best = std::max(best, IoU(d.box, truth));
        ++total;
        found += best >= 0.5;
        std::printf("%s %s car (%.0f,%.0f)-(%.0f,%.0f): best IoU %.2f\n", model, frame.image.c_str(), truth.x, truth.y,
                    truth.br().x, truth.br().y, best);
      }
    }
    EXPECT_EQ(found, total) << model;
  }
}

// Letterboxing (aspect kept, padded) maps boxes back to the image correctly: the
// nearest car is found at its place (smaller, farther cars suffer from the 0.28 scale).
TEST(DetectorTest, LetterboxedInputFindsTheNearCars) {
  SPECHT_REQUIRE_FILE(ModelsDir());
  DetectorOptions options = ShippedModel("fastestdet");
  options.letterbox = true;  // 352 × 352 with bands above and below
  Detector detector(options, testing::DataDir());
  const auto& frame = Expected()[2];  // the KITTI object frame
  const auto detections = detector.Detect(cv::imread(testing::DataDir() + "/stereo/" + frame.image));
  double best = 0;
  for (const auto& d : detections)
    if (d.cls == "car") best = std::max(best, IoU(d.box, frame.cars[0]));
  EXPECT_GE(best, 0.8);
  // FastestDet's graph is fixed to 352 × 352: another input size is reported, not thrown raw.
  options.input_width = 640;
  try {
    Detector wrong(options, testing::DataDir());
    wrong.Detect(cv::Mat(100, 100, CV_8UC3, cv::Scalar::all(0)));
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("cannot run at 640×352"));
  }
}

// Acceptance 2: for each car or pedestrian detected on the KITTI 2015 frames within
// 30 m, the fused distance against the reference distance: the object's disparity in
// the ground truth, taken as the nearest mode of the ground-truth disparities inside
// the same box (the object is the nearest surface filling the box centre). Median
// relative error ≤ 5 % for the default method (both are printed).
TEST(FusionTest, BoxDistanceAgreesWithGroundTruth) {
  SPECHT_REQUIRE_FILE(ModelsDir());
  Detector detector(ShippedModel("yolo-fastest"), testing::DataDir());
  const stereo::RectifiedCamera camera{cv::Size(1242, 375), 721.5377, 609.5593, 172.854, 0.5327};  // KITTI 2015 P2/P3
  FusionOptions reference_options;                                                                 // nearest mode
  reference_options.mode_min_share = 0.15;
  for (const char* method : {"centre", "nearest_mode"}) {
    FusionOptions options;
    options.method = method;
    std::vector<double> errors;
    for (const char* frame : {"000000_10", "000001_10"}) {
      const std::string dir = testing::DataDir() + "/stereo/kitti2015/";
      const cv::Mat left = cv::imread(dir + "image_2/" + frame + ".png");
      const cv::Mat disparity =
          stereo::ComputeDisparity(stereo::ReadGray8(dir + "image_2/" + frame + ".png"),
                                   stereo::ReadGray8(dir + "image_3/" + frame + ".png"), stereo::SgmOptions());
      const cv::Mat truth = stereo::ReadDisparityPng(dir + "disp_occ_0/" + frame + ".png");
      for (const auto& d : detector.Detect(left)) {
        if (d.cls != "car" && d.cls != "pedestrian") continue;
        const double reference_d = BoxDisparity(d.box, truth, reference_options);
        if (!(reference_d > 0) || camera.DepthOf(reference_d) > 30) continue;
        const auto o = Fuse(d, disparity, camera, options);
        const double reference_m = camera.DepthOf(reference_d);
        const double error = o ? std::abs(o->distance_m - reference_m) / reference_m : 1.0;
        std::printf("%s %s %s at %.1f m: fused %.2f m (%.1f %%)\n", method, frame, d.cls.c_str(), reference_m,
                    o ? o->distance_m : -1.0, 100 * error);
        errors.push_back(error);
      }
    }
    ASSERT_GE(errors.size(), 3u) << method;
    std::nth_element(errors.begin(), errors.begin() + static_cast<long>(errors.size() / 2), errors.end());
    const double median = errors[errors.size() / 2];
    std::printf("%s: median relative distance error %.2f %% over %zu objects\n", method, 100 * median, errors.size());
    // The paper's centre pixel falls on background or a window often enough to miss
    // the target; it is reported, the default (nearest mode) is held to it.
    if (std::string(method) == "nearest_mode") {
      EXPECT_LE(median, 0.05) << method;
    }
  }
}

// Acceptance 2, KITTI object frame: the fused distance against the LiDAR points
// projected into the same box (their nearest mode), for cars within 30 m.
TEST(FusionTest, BoxDistanceAgreesWithLidar) {
  SPECHT_REQUIRE_FILE(ModelsDir());
  const std::string dir = testing::DataDir() + "/stereo/kitti_object/";
  const stereo::StereoCalibration calib = stereo::LoadCalibration({dir + "calib.txt"});
  const cv::Mat left = stereo::ReadGray8(dir + "left.png");
  const cv::Mat lidar = stereo::ProjectLidarToDisparity(stereo::ReadVelodyne(dir + "lidar.bin"), calib, left.size());
  const cv::Mat disparity = stereo::ComputeDisparity(left, stereo::ReadGray8(dir + "right.png"), stereo::SgmOptions());
  Detector detector(ShippedModel("yolo-fastest"), testing::DataDir());
  FusionOptions sparse_reference;
  sparse_reference.inner_fraction = 0.8;
  for (const char* method : {"centre", "nearest_mode"}) {
    FusionOptions options;
    options.method = method;
    std::vector<double> errors;
    for (const auto& d : detector.Detect(cv::imread(dir + "left.png"))) {
      if (d.cls != "car") continue;
      const double reference_d = BoxDisparity(d.box, lidar, sparse_reference);
      if (!(reference_d > 0) || calib.camera.DepthOf(reference_d) > 30) continue;
      const auto o = Fuse(d, disparity, calib.camera, options);
      const double reference_m = calib.camera.DepthOf(reference_d);
      errors.push_back(o ? std::abs(o->distance_m - reference_m) / reference_m : 1.0);
    }
    ASSERT_GE(errors.size(), 3u);
    std::nth_element(errors.begin(), errors.begin() + static_cast<long>(errors.size() / 2), errors.end());
    std::printf("%s vs LiDAR: median relative distance error %.2f %% over %zu cars\n", method,
                100 * errors[errors.size() / 2], errors.size());
    if (std::string(method) == "nearest_mode") {
      EXPECT_LE(errors[errors.size() / 2], 0.05);
    }
  }
}

// Acceptance 5: bad input names what and where.
// A person on a bicycle is one cyclist (the union box); a person beside one is not.
TEST(DetectorTest, ARiderAndHerBicycleBecomeOneCyclist) {
  using detect::Detection;
  const std::vector<Detection> in = {{{100, 100, 40, 80}, "pedestrian", "person", 0.9},
                                     {{95, 140, 55, 50}, "cyclist", "bicycle", 0.4},
                                     {{300, 100, 30, 80}, "pedestrian", "person", 0.8},
                                     {{340, 150, 50, 40}, "cyclist", "bicycle", 0.6}};
  const auto out = detect::MergeRiders(in, 0.5);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0].cls, "cyclist");
  EXPECT_EQ(out[0].box, cv::Rect2d(95, 100, 55, 90));
  EXPECT_DOUBLE_EQ(out[0].score, 0.9);
  EXPECT_EQ(out[1].cls, "pedestrian");  // beside the other bicycle: not on it
  EXPECT_EQ(out[2].box, in[3].box);
  EXPECT_EQ(detect::MergeRiders(in, 0.99).size(), 4u);
}

TEST(DetectorTest, BadInputIsReportedClearly) {
  SPECHT_REQUIRE_FILE(ModelsDir());
  auto error_of = [](const DetectorOptions& o, const cv::Mat& image = cv::Mat(64, 64, CV_8UC3)) {
    try {
      Detector detector(o, testing::DataDir());
      detector.Detect(image);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  DetectorOptions missing = ShippedModel("yolo-fastest");
  missing.model = "models/nothing.weights";
  EXPECT_THAT(error_of(missing), HasSubstr("nothing.weights: model not found"));
  // The ONNX model given to the darknet decoder's configuration and vice versa.
  DetectorOptions swapped = ShippedModel("fastestdet");
  swapped.labels = testing::TempDir() + "/three.names";
  testing::WriteFile(swapped.labels, "a\nb\nc\n");
  EXPECT_THAT(error_of(swapped), HasSubstr("does not fit the fastestdet_onnx decoder with 3 labels"));
  DetectorOptions not_a_model = ShippedModel("fastestdet");
  not_a_model.model = "models/coco.names";
  EXPECT_THAT(error_of(not_a_model), HasSubstr("cannot load"));
  EXPECT_THAT(error_of(ShippedModel("yolo-fastest"), cv::Mat(64, 64, CV_16UC1)), HasSubstr("8-bit"));
  EXPECT_THAT(error_of(ShippedModel("yolo-fastest"), cv::Mat()), HasSubstr("empty"));
  DetectorOptions bad_map = ShippedModel("yolo-fastest");
  bad_map.class_map = {"car=automobile"};
  EXPECT_THAT(error_of(bad_map), HasSubstr("not a driving class"));
}

}  // namespace
}  // namespace specht::detect
