// One stereo pair (stereo_pair.h): its disparity, and with a calibration its depth,
// point cloud and OctoMap:
//   disparity.png        KITTI uint16 (value / 256 = px, 0 = no estimate)
//   disparity_color.png  the disparity on a fixed colour scale (black = none)
//   hints.png            the sparse hints used (KITTI uint16), when guided
//   comparison.png       half-size preview: left image, unguided and guided disparity
//   depth.png            uint16 millimetres (0 = none), depth_color.png  (with --calib)
//   points.ply           coloured points, camera frame or --frame (with --calib)
//   octomap.bt           OctoMap of the points from the camera origin (with --calib)
//   report.json/.md      matcher, instruction set, timings, density, left-right
//                        consistency; when guided, the same for the unguided run
#include "specht/pipeline/stereo_pair.h"

#include <cstdio>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "specht/core/error.h"
#include "specht/core/transform_tree.h"
#include "specht/io/map_io.h"
#include "specht/io/report.h"
#include "specht/pipeline/run_directory.h"
#include "specht/stereo/calibration.h"
#include "specht/stereo/guidance.h"
#include "specht/stereo/images.h"
#include "specht/stereo/point_cloud.h"
#include "specht/stereo/sgm.h"

namespace specht::pipeline {
namespace {

struct MatchRun {
  cv::Mat disparity;
  stereo::MatchStats stats;
  double ms = 0;
  std::string isa;
};

// `matcher` is ours (kept between the guided and unguided runs) or null for OpenCV's.
MatchRun Match(const cv::Mat& left, const cv::Mat& right, const stereo::SgmOptions& o,
               stereo::SemiGlobalMatcher* matcher, const stereo::Guidance* g) {
  MatchRun run;
  io::StageTimer timer;
  {
    auto t = timer.Time("match");
    if (matcher != nullptr) {
      run.disparity = matcher->Compute(left, right, g);
      run.stats = matcher->last_stats();
      run.isa = matcher->instruction_set();
    } else {
      run.disparity = stereo::ComputeDisparity(left, right, o, g);
      run.isa = "opencv";
    }
  }
  run.ms = timer.TotalMs("match");
  return run;
}

nlohmann::json Summary(const MatchRun& run) {
  const double pixels = static_cast<double>(run.disparity.total());
  return {{"ms", run.ms},
          {"instruction_set", run.isa},
          {"density", cv::countNonZero(run.disparity > 0) / pixels},
          {"lr_consistency", run.stats.lr_consistency()},
          {"unique_fraction", run.stats.unique / pixels}};
}

}  // namespace

int RunStereoPair(const params::Params& params, const StereoPairInputs& a, const std::string& out) {
  const auto& sgm = params.Get<stereo::SgmOptions>("stereo");
  const auto& cloud_options = params.Get<stereo::CloudOptions>("stereo_cloud");
  cv::Mat left_colour = cv::imread(a.left, cv::IMREAD_COLOR);
  cv::Mat left = stereo::ReadGray8(a.left), right = stereo::ReadGray8(a.right);
  if (left.size() != right.size())
    throw InputError(a.right + ": " + std::to_string(right.cols) + "×" + std::to_string(right.rows) +
                     " differs from the left image's " + std::to_string(left.cols) + "×" + std::to_string(left.rows));

  std::optional<stereo::StereoCalibration> calibration;
  std::optional<stereo::RectifiedCamera> camera;
  if (!a.calib.empty()) {
    calibration = stereo::LoadCalibration(a.calib);
    stereo::CheckImageSize(*calibration, left.size());
    if (calibration->rectified) {
      camera = calibration->camera;
    } else {
      const stereo::Rectifier rectifier(*calibration);
      rectifier.Rectify(left, right, left, right);
      cv::Mat rectified_colour, unused;
      rectifier.Rectify(left_colour, left_colour, rectified_colour, unused);
      left_colour = rectified_colour;
      camera = rectifier.camera();
    }
    camera->size = left.size();
  }

  std::optional<stereo::Guidance> guidance;
  if (!a.hints.empty() && !a.lidar.empty()) throw InputError("--hints and --lidar: give one of them");
  if (!a.hints.empty()) {
    const cv::Mat hints = stereo::ReadDisparityPng(a.hints);
    if (hints.size() != left.size())
      throw InputError(a.hints + ": hints are " + std::to_string(hints.cols) + "×" + std::to_string(hints.rows) +
                       ", the images " + std::to_string(left.cols) + "×" + std::to_string(left.rows));
    guidance = stereo::HintsGuidance(hints);
  } else if (!a.lidar.empty()) {
    if (!calibration) throw InputError("--lidar needs --calib (KITTI calib.txt with Tr_velo_to_cam)");
    guidance = stereo::HintsGuidance(
        stereo::ProjectLidarToDisparity(stereo::ReadVelodyne(a.lidar), *calibration, left.size()));
  } else if (a.ground_height_m > 0) {
    if (!camera) throw InputError("--ground-height needs --calib (focal length, principal point, baseline)");
    stereo::GroundPlane plane{camera->focal_px, camera->cy_px, camera->baseline_m, a.ground_height_m,
                              a.ground_pitch_deg * M_PI / 180};
    guidance = stereo::PriorGuidance(stereo::GroundPlaneDisparity(plane, left.size(), sgm.num_disparities), 1.0);
  }

  PrepareRunDirectory(out, params);
  io::RunReport report("stereo");
  auto& j = report.json();
  j["inputs"] = {
      {"left", a.left}, {"right", a.right}, {"size", std::to_string(left.cols) + "x" + std::to_string(left.rows)}};
  std::unique_ptr<stereo::SemiGlobalMatcher> matcher;
  if (sgm.matcher == "specht") matcher = std::make_unique<stereo::SemiGlobalMatcher>(sgm);
  const MatchRun run = Match(left, right, sgm, matcher.get(), guidance ? &*guidance : nullptr);
  j["metrics"]["match"] = Summary(run);
  if (guidance) {
    const MatchRun unguided = Match(left, right, sgm, matcher.get(), nullptr);
    j["metrics"]["unguided"] = Summary(unguided);
    // Half-size preview: the left image, the unguided and the guided disparity.
    cv::Mat left_bgr, preview;
    cv::cvtColor(left, left_bgr, cv::COLOR_GRAY2BGR);
    cv::vconcat(std::vector<cv::Mat>{left_bgr, stereo::ColorizeDisparity(unguided.disparity, sgm.num_disparities),
                                     stereo::ColorizeDisparity(run.disparity, sgm.num_disparities)},
                preview);
    cv::resize(preview, preview, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
    io::WritePng(preview, out + "/comparison.png");
    report.AddOutput("comparison.png");
    j["metrics"]["guide_density"] = cv::countNonZero(guidance->disparity > 0) / static_cast<double>(left.total());
    stereo::WriteDisparityKitti(guidance->disparity, out + "/hints.png");
    report.AddOutput("hints.png");
  }
  stereo::WriteDisparityKitti(run.disparity, out + "/disparity.png");
  io::WritePng(stereo::ColorizeDisparity(run.disparity, sgm.num_disparities), out + "/disparity_color.png");
  report.AddOutput("disparity.png");
  report.AddOutput("disparity_color.png");

  if (camera) {
    const cv::Mat depth = stereo::DepthFromDisparity(run.disparity, *camera);
    cv::Mat depth_mm;
    depth.convertTo(depth_mm, CV_16U, 1000.0);
    io::WritePng(depth_mm, out + "/depth.png");
    io::WritePng(stereo::ColorizeDepth(depth, cloud_options.max_depth_m), out + "/depth_color.png");
    std::vector<stereo::ColouredPoint> points = stereo::DisparityToPoints(
        run.disparity, *camera, left_colour.size() == left.size() ? left_colour : left, cloud_options);
    octomap::OcTree tree(cloud_options.octree_resolution_m);
    stereo::InsertIntoOctree(tree, points, cv::Point3f(0, 0, 0), cloud_options);
    mrpt::poses::CPose3D target_from_camera;
    if (!a.frame.empty() && a.frame != a.camera_frame) {
      const TransformTree frames(params.Get<FramesOptions>("frames"));
      target_from_camera = frames.LookupStatic(a.frame, a.camera_frame);
      stereo::TransformPoints(points, target_from_camera);
    }
    stereo::WritePly(points, out + "/points.ply");
    stereo::WriteOctree(tree, out + "/octomap.bt");
    j["metrics"]["points"] = points.size();
    j["metrics"]["octree_occupied_leaves"] = [&] {
      size_t n = 0;
      for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) n += tree.isNodeOccupied(*it);
      return n;
    }();
    j["frames"] = {{"points", a.frame.empty() ? a.camera_frame : a.frame}, {"octomap", a.camera_frame}};
    for (const char* f : {"depth.png", "depth_color.png", "points.ply", "octomap.bt"}) report.AddOutput(f);
  }
  report.Write(out);
  const auto& m = j["metrics"]["match"];
  std::printf("stereo: %s, %.1f ms, density %.1f %%, left-right consistency %.1f %%\n", run.isa.c_str(), run.ms,
              100 * m["density"].get<double>(), 100 * m["lr_consistency"].get<double>());
  if (guidance) {
    const auto& u = j["metrics"]["unguided"];
    std::printf("unguided: density %.1f %%, left-right consistency %.1f %%\n", 100 * u["density"].get<double>(),
                100 * u["lr_consistency"].get<double>());
  }
  return 0;
}

}  // namespace specht::pipeline
